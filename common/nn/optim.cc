#include "common/nn/optim.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace srics::nn {
namespace {

template <typename T>
void Append(std::vector<float>& out, const Matrix<T>& m) {
  for (Eigen::Index i = 0; i < m.size(); ++i) out.push_back(static_cast<float>(m.data()[i]));
}

template <typename T>
size_t Read(const std::vector<float>& in, size_t pos, Matrix<T>& m) {
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = static_cast<T>(in[pos + i]);
  return pos + static_cast<size_t>(m.size());
}

constexpr std::int64_t kHalf = std::int64_t{1} << 24;

}  // namespace

template <typename T, typename Rule>
Optimizer<T, Rule>::Optimizer(ParameterList<T> params, Options options)
    : params_(std::move(params)), options_(options), moments_(params_.size()) {
  for (size_t i = 0; i < params_.size(); ++i)
    for (Matrix<T>& m : moments_[i]) m.setZero(params_[i]->value.rows(), params_[i]->value.cols());
}

template <typename T, typename Rule>
void Optimizer<T, Rule>::Step() {
  ++steps_;
  for (size_t i = 0; i < params_.size(); ++i) Rule::Update(options_, steps_, *params_[i], moments_[i]);
}

// The state: two header slots (the step count split in 24-bit halves so floats hold it
// exactly), then moment by moment, every parameter's values.
template <typename T, typename Rule>
std::vector<float> Optimizer<T, Rule>::ExportState() const {
  std::vector<float> out{static_cast<float>(steps_ / kHalf), static_cast<float>(steps_ % kHalf)};
  out.reserve(2 + Rule::kMoments * static_cast<size_t>(NumScalars(params_)));
  for (int k = 0; k < Rule::kMoments; ++k)
    for (const auto& moments : moments_) Append(out, moments[k]);
  return out;
}

template <typename T, typename Rule>
void Optimizer<T, Rule>::ImportState(const std::vector<float>& state) {
  const size_t expected = 2 + Rule::kMoments * static_cast<size_t>(NumScalars(params_));
  if (state.size() != expected) {
    throw std::invalid_argument(std::string(Rule::kName) + "::ImportState: " + std::to_string(state.size()) +
                                " values, expected " + std::to_string(expected));
  }
  steps_ = static_cast<std::int64_t>(state[0]) * kHalf + static_cast<std::int64_t>(state[1]);
  size_t pos = 2;
  for (int k = 0; k < Rule::kMoments; ++k)
    for (auto& moments : moments_) pos = Read(state, pos, moments[k]);
}

template <typename T>
void AdamRule::Update(const Options& o, std::int64_t step, Parameter<T>& p, std::array<Matrix<T>, 2>& moments) {
  const double c1 = 1.0 - std::pow(o.beta1, static_cast<double>(step));
  const double c2 = 1.0 - std::pow(o.beta2, static_cast<double>(step));
  const T b1 = static_cast<T>(o.beta1), b2 = static_cast<T>(o.beta2);
  const T lr = static_cast<T>(o.lr / c1);
  const T inv_sqrt_c2 = static_cast<T>(1.0 / std::sqrt(c2));
  const T eps = static_cast<T>(o.eps);
  const auto g = p.grad.array();
  auto m = moments[0].array();
  auto v = moments[1].array();
  m = b1 * m + (T(1) - b1) * g;
  v = b2 * v + (T(1) - b2) * g.square();
  // p -= lr * m_hat / (sqrt(v_hat) + eps)
  p.value.array() -= lr * m / (v.sqrt() * inv_sqrt_c2 + eps);
}

template <typename T>
void RmsPropRule::Update(const Options& o, std::int64_t, Parameter<T>& p, std::array<Matrix<T>, 1>& moments) {
  const T a = static_cast<T>(o.alpha), lr = static_cast<T>(o.lr);
  const T eps = static_cast<T>(o.eps);
  const auto g = p.grad.array();
  auto v = moments[0].array();
  v = a * v + (T(1) - a) * g.square();
  p.value.array() -= lr * g / (v.sqrt() + eps);
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
bool GradientsUsable(const ParameterList<T>& params) {
  const T most = static_cast<T>(kMaxUsableGradient);
  // one vector pass over each gradient, no early exit (Eigen's all() of a comparison tested
  // one value at a time: 2-3% of a batch-256 run's CPU time, twice per update)
  int unusable = 0;
  for (const Parameter<T>* p : params) {
    const T* g = p->grad.data();
    const Eigen::Index n = p->grad.size();
#pragma omp simd reduction(| : unusable)
    for (Eigen::Index i = 0; i < n; ++i) unusable |= !(std::abs(g[i]) <= most);  // NaN fails too
  }
  return unusable == 0;
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

template class Optimizer<float, AdamRule>;
template class Optimizer<double, AdamRule>;
template class Optimizer<float, RmsPropRule>;
template class Optimizer<double, RmsPropRule>;
template double ClipGradNorm<float>(const ParameterList<float>&, double);
template double ClipGradNorm<double>(const ParameterList<double>&, double);
template bool GradientsUsable<float>(const ParameterList<float>&);
template bool GradientsUsable<double>(const ParameterList<double>&);
template void SoftUpdate<float>(const ParameterList<float>&, const ParameterList<float>&, double);
template void SoftUpdate<double>(const ParameterList<double>&, const ParameterList<double>&, double);

}  // namespace srics::nn
