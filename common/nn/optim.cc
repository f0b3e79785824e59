#include "common/nn/optim.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace srics::nn {
namespace {

template <typename T>
std::vector<Matrix<T>> ZerosLike(const ParameterList<T>& params) {
  std::vector<Matrix<T>> out;
  for (const Parameter<T>* p : params) {
    out.push_back(Matrix<T>::Zero(p->value.rows(), p->value.cols()));
  }
  return out;
}

template <typename T>
void Append(std::vector<float>& out, const Matrix<T>& m) {
  for (Eigen::Index i = 0; i < m.size(); ++i) out.push_back(static_cast<float>(m.data()[i]));
}

template <typename T>
size_t Read(const std::vector<float>& in, size_t pos, Matrix<T>& m) {
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = static_cast<T>(in[pos + i]);
  return pos + static_cast<size_t>(m.size());
}

// two header slots: the step count split in 24-bit halves so floats hold it exactly
template <typename T>
size_t StateSize(const ParameterList<T>& params, int slots) {
  return 2 + slots * static_cast<size_t>(NumScalars(params));
}

constexpr std::int64_t kHalf = std::int64_t{1} << 24;

}  // namespace

template <typename T>
Adam<T>::Adam(ParameterList<T> params, Options options)
    : params_(std::move(params)), options_(options), m_(ZerosLike(params_)),
      v_(ZerosLike(params_)) {}

template <typename T>
void Adam<T>::Step() {
  ++steps_;
  const double c1 = 1.0 - std::pow(options_.beta1, static_cast<double>(steps_));
  const double c2 = 1.0 - std::pow(options_.beta2, static_cast<double>(steps_));
  const T b1 = static_cast<T>(options_.beta1), b2 = static_cast<T>(options_.beta2);
  const T step = static_cast<T>(options_.lr / c1);
  const T inv_sqrt_c2 = static_cast<T>(1.0 / std::sqrt(c2));
  const T eps = static_cast<T>(options_.eps);
  for (size_t i = 0; i < params_.size(); ++i) {
    const auto g = params_[i]->grad.array();
    auto m = m_[i].array();
    auto v = v_[i].array();
    m = b1 * m + (T(1) - b1) * g;
    v = b2 * v + (T(1) - b2) * g.square();
    // p -= lr * m_hat / (sqrt(v_hat) + eps)
    params_[i]->value.array() -= step * m / (v.sqrt() * inv_sqrt_c2 + eps);
  }
}

template <typename T>
std::vector<float> Adam<T>::ExportState() const {
  std::vector<float> out;
  out.reserve(StateSize(params_, 2));
  out.push_back(static_cast<float>(steps_ / kHalf));
  out.push_back(static_cast<float>(steps_ % kHalf));
  for (const auto& m : m_) Append(out, m);
  for (const auto& v : v_) Append(out, v);
  return out;
}

template <typename T>
void Adam<T>::ImportState(const std::vector<float>& state) {
  if (state.size() != StateSize(params_, 2)) {
    throw std::invalid_argument("nn::Adam::ImportState: " + std::to_string(state.size()) +
                                " values, expected " + std::to_string(StateSize(params_, 2)));
  }
  steps_ = static_cast<std::int64_t>(state[0]) * kHalf + static_cast<std::int64_t>(state[1]);
  size_t pos = 2;
  for (auto& m : m_) pos = Read(state, pos, m);
  for (auto& v : v_) pos = Read(state, pos, v);
}

template <typename T>
RmsProp<T>::RmsProp(ParameterList<T> params, Options options)
    : params_(std::move(params)), options_(options), v_(ZerosLike(params_)) {}

template <typename T>
void RmsProp<T>::Step() {
  const T a = static_cast<T>(options_.alpha), lr = static_cast<T>(options_.lr);
  const T eps = static_cast<T>(options_.eps);
  for (size_t i = 0; i < params_.size(); ++i) {
    const auto g = params_[i]->grad.array();
    auto v = v_[i].array();
    v = a * v + (T(1) - a) * g.square();
    params_[i]->value.array() -= lr * g / (v.sqrt() + eps);
  }
}

template <typename T>
std::vector<float> RmsProp<T>::ExportState() const {
  std::vector<float> out;
  out.push_back(0.0f);  // keeps the layout of Adam: two header slots, then the moments
  out.push_back(0.0f);
  for (const auto& v : v_) Append(out, v);
  return out;
}

template <typename T>
void RmsProp<T>::ImportState(const std::vector<float>& state) {
  if (state.size() != StateSize(params_, 1)) {
    throw std::invalid_argument("nn::RmsProp::ImportState: " + std::to_string(state.size()) +
                                " values, expected " + std::to_string(StateSize(params_, 1)));
  }
  size_t pos = 2;
  for (auto& v : v_) pos = Read(state, pos, v);
}

template <typename T>
double ClipGradNorm(const ParameterList<T>& params, double max_norm) {
  double sq = 0;
  for (const Parameter<T>* p : params) sq += static_cast<double>(p->grad.squaredNorm());
  const double norm = std::sqrt(sq);
  if (norm > max_norm && norm > 0) {
    const T scale = static_cast<T>(max_norm / (norm + 1e-12));
    for (Parameter<T>* p : params) p->grad *= scale;
  }
  return norm;
}

template <typename T>
void SoftUpdate(const ParameterList<T>& target, const ParameterList<T>& source, double tau) {
  if (target.size() != source.size()) {
    throw std::invalid_argument("nn::SoftUpdate: parameter lists differ in length");
  }
  const T t = static_cast<T>(tau);
  for (size_t i = 0; i < target.size(); ++i) {
    Matrix<T>& dst = target[i]->value;
    const Matrix<T>& src = source[i]->value;
    if (dst.rows() != src.rows() || dst.cols() != src.cols()) {
      throw std::invalid_argument("nn::SoftUpdate: shape mismatch at " + target[i]->name);
    }
    if (tau == 1.0) {
      dst = src;
    } else {
      dst = (T(1) - t) * dst + t * src;
    }
  }
}

template class Adam<float>;
template class Adam<double>;
template class RmsProp<float>;
template class RmsProp<double>;
template double ClipGradNorm<float>(const ParameterList<float>&, double);
template double ClipGradNorm<double>(const ParameterList<double>&, double);
template void SoftUpdate<float>(const ParameterList<float>&, const ParameterList<float>&,
                                double);
template void SoftUpdate<double>(const ParameterList<double>&, const ParameterList<double>&,
                                 double);

}  // namespace srics::nn
