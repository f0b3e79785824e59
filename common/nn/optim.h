#pragma once
// Optimizers and parameter-list utilities. An optimizer keeps one state slot per parameter
// of the list it was built with (index-aligned, named after the parameter), never keyed by
// memory address; its state can be exported and imported for checkpoints.

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "common/nn/tensor.h"

namespace srics::nn {

// A first-order optimizer: the parameter list it was built with, the options of its update
// rule (Adam, RmsProp below), a step count and Rule::kMoments state slots per parameter.
// Rule provides Options (with an `lr` field), kName (for errors), kMoments and
// Update(options, step, parameter, moments) applying one step to one parameter.
template <typename T, typename Rule>
class Optimizer {
 public:
  using Options = typename Rule::Options;

  Optimizer(ParameterList<T> params, Options options);

  // One update from the parameters' current gradients (gradients are left unchanged).
  void Step();
  // Zeroes the gradients of the optimized parameters.
  void ZeroGrad() { nn::ZeroGrad(params_); }
  void set_lr(double lr) { options_.lr = lr; }
  const Options& options() const { return options_; }
  const ParameterList<T>& parameters() const { return params_; }
  // Updates done so far.
  std::int64_t steps() const { return steps_; }

  // The full state (step count, then every moment of every parameter) as floats, for
  // checkpoints.
  std::vector<float> ExportState() const;
  // Restores ExportState output; throws std::invalid_argument on a size mismatch.
  void ImportState(const std::vector<float>& state);

 private:
  ParameterList<T> params_;
  Options options_;
  std::int64_t steps_ = 0;
  std::vector<std::array<Matrix<T>, Rule::kMoments>> moments_;  // per parameter
};

// Adam (Kingma & Ba) with bias correction, as in PyTorch (eps added after the square root).
// Moments: first, second.
struct AdamRule {
  struct Options {
    double lr = 1e-3;
    double beta1 = 0.9;
    double beta2 = 0.999;
    double eps = 1e-8;
  };
  static constexpr const char* kName = "nn::Adam";
  static constexpr int kMoments = 2;
  template <typename T>
  static void Update(const Options& o, std::int64_t step, Parameter<T>& p, std::array<Matrix<T>, 2>& moments);
};

// RMSprop as in PyTorch (no momentum, not centered): v = a v + (1 - a) g^2,
// p -= lr g / (sqrt(v) + eps). Moment: v.
struct RmsPropRule {
  struct Options {
    double lr = 1e-2;
    double alpha = 0.99;
    double eps = 1e-8;
  };
  static constexpr const char* kName = "nn::RmsProp";
  static constexpr int kMoments = 1;
  template <typename T>
  static void Update(const Options& o, std::int64_t step, Parameter<T>& p, std::array<Matrix<T>, 1>& moments);
};

template <typename T>
using Adam = Optimizer<T, AdamRule>;
template <typename T>
using RmsProp = Optimizer<T, RmsPropRule>;

extern template class Optimizer<float, AdamRule>;
extern template class Optimizer<double, AdamRule>;
extern template class Optimizer<float, RmsPropRule>;
extern template class Optimizer<double, RmsPropRule>;

// Scales all gradients so that their joint L2 norm is at most max_norm; returns the norm
// before clipping.
template <typename T>
double ClipGradNorm(const ParameterList<T>& params, double max_norm);

// Beyond this a gradient's square, which Adam and RmsProp add into their second moments,
// overflows float (FLT_MAX is 3.4e38): the moment becomes infinite and the next step NaN. A
// finite input of 1e12 gave such gradients with a finite loss (SacTest.NonFiniteBatchChangesNoNetwork).
inline constexpr double kMaxUsableGradient = 1e18;

// True when every gradient of `params` is finite and at most kMaxUsableGradient in magnitude:
// checked before an optimizer step, which is skipped otherwise (SAC, the graph's GNN).
template <typename T>
bool GradientsUsable(const ParameterList<T>& params);

// target = (1 - tau) target + tau source, parameter by parameter (lists must match in
// order and shapes; throws std::invalid_argument otherwise). tau = 1 copies.
template <typename T>
void SoftUpdate(const ParameterList<T>& target, const ParameterList<T>& source, double tau);

}  // namespace srics::nn
