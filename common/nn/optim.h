// Optimizers and parameter-list utilities. An optimizer keeps one state slot per parameter
// of the list it was built with (index-aligned, named after the parameter), never keyed by
// memory address; its state can be exported and imported for checkpoints.
#ifndef SRICS_COMMON_NN_OPTIM_H_
#define SRICS_COMMON_NN_OPTIM_H_

#include <cstdint>
#include <vector>

#include "common/nn/tensor.h"

namespace srics::nn {

// Adam (Kingma & Ba) with bias correction, as in PyTorch (eps added after the square root).
template <typename T>
class Adam {
 public:
  struct Options {
    double lr = 1e-3;
    double beta1 = 0.9;
    double beta2 = 0.999;
    double eps = 1e-8;
  };
  Adam(ParameterList<T> params, Options options);

  // One update from the parameters' current gradients (gradients are left unchanged).
  void Step();
  // Zeroes the gradients of the optimized parameters.
  void ZeroGrad() { nn::ZeroGrad(params_); }

  void set_lr(double lr) { options_.lr = lr; }
  const Options& options() const { return options_; }
  std::int64_t steps() const { return steps_; }
  const ParameterList<T>& parameters() const { return params_; }

  // The full state (step count, first and second moments) as floats, for checkpoints.
  std::vector<float> ExportState() const;
  // Restores ExportState output; throws std::invalid_argument on a size mismatch.
  void ImportState(const std::vector<float>& state);

 private:
  ParameterList<T> params_;
  Options options_;
  std::int64_t steps_ = 0;
  std::vector<Matrix<T>> m_, v_;
};

// RMSprop as in PyTorch (no momentum, not centered): v = a v + (1 - a) g^2,
// p -= lr g / (sqrt(v) + eps).
template <typename T>
class RmsProp {
 public:
  struct Options {
    double lr = 1e-2;
    double alpha = 0.99;
    double eps = 1e-8;
  };
  RmsProp(ParameterList<T> params, Options options);

  void Step();
  void ZeroGrad() { nn::ZeroGrad(params_); }
  void set_lr(double lr) { options_.lr = lr; }
  const ParameterList<T>& parameters() const { return params_; }

  std::vector<float> ExportState() const;
  void ImportState(const std::vector<float>& state);

 private:
  ParameterList<T> params_;
  Options options_;
  std::vector<Matrix<T>> v_;
};

// Scales all gradients so that their joint L2 norm is at most max_norm; returns the norm
// before clipping.
template <typename T>
double ClipGradNorm(const ParameterList<T>& params, double max_norm);

// target = (1 - tau) target + tau source, parameter by parameter (lists must match in
// order and shapes; throws std::invalid_argument otherwise). tau = 1 copies.
template <typename T>
void SoftUpdate(const ParameterList<T>& target, const ParameterList<T>& source, double tau);

}  // namespace srics::nn

#endif  // SRICS_COMMON_NN_OPTIM_H_
