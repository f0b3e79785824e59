#pragma once
// Tensors and trainable parameters: plain Eigen matrices with a scalar type parameter, so that
// the same code runs in float (training, inference) and double (gradient checks).

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace srics::nn {

// A 2-D tensor. Rows are samples (or sample x entity pairs); row-major so that a row is
// contiguous and reshapes keep the element order.
template <typename T>
using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Float tensor, the type used everywhere outside of gradient checks.
using Tensor = Matrix<float>;

// The random generator used by initialisers, sampling and Gumbel noise.
using Rng = std::mt19937_64;

// A trainable tensor with its accumulated gradient. Modules own their parameters through
// unique_ptr so that a parameter's address is stable for optimizers and tapes.
template <typename T>
struct Parameter {
  // Creates a zero parameter called `name` of shape rows x cols.
  Parameter(std::string name, Eigen::Index rows, Eigen::Index cols)
      : name(std::move(name)), value(Matrix<T>::Zero(rows, cols)), grad(Matrix<T>::Zero(rows, cols)) {}

  std::string name;  // unique, dotted path such as "policy.mlp.0.w"
  Matrix<T> value;
  Matrix<T> grad;  // accumulated by Tape::Backward until ZeroGrad
};

// The ordered parameter list of a model; the order defines the flat layout and signature.
template <typename T>
using ParameterList = std::vector<Parameter<T>*>;

// Sets every gradient to zero.
template <typename T>
void ZeroGrad(const ParameterList<T>& params) {
  for (Parameter<T>* p : params) p->grad.setZero();
}

// Total number of scalars in `params`.
template <typename T>
std::int64_t NumScalars(const ParameterList<T>& params) {
  std::int64_t n = 0;
  for (const Parameter<T>* p : params) n += p->value.size();
  return n;
}

// Fills `m` with Xavier (Glorot) uniform values for a layer of fan_in -> fan_out.
template <typename T>
void XavierUniform(Matrix<T>& m, Eigen::Index fan_in, Eigen::Index fan_out, Rng& rng) {
  const double a = std::sqrt(6.0 / static_cast<double>(fan_in + fan_out));
  std::uniform_real_distribution<double> u(-a, a);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = static_cast<T>(u(rng));
}

// A rows x cols matrix of independent standard normal samples.
template <typename T>
Matrix<T> RandomNormal(Eigen::Index rows, Eigen::Index cols, Rng& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Matrix<T> m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = static_cast<T>(n(rng));
  return m;
}

// A rows x cols matrix of independent standard Gumbel samples (-log(-log(u))).
template <typename T>
Matrix<T> RandomGumbel(Eigen::Index rows, Eigen::Index cols, Rng& rng) {
  std::uniform_real_distribution<double> u(1e-10, 1.0);
  Matrix<T> m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    m.data()[i] = static_cast<T>(-std::log(-std::log(u(rng))));
  }
  return m;
}

}  // namespace srics::nn
