#pragma once
// Shared by the benchmarks: medians of repeated timings, and the "GEMM floor": the very
// matrix products a tape executed (logged with Tape::set_gemm_log), replayed as bare Eigen
// products on preallocated operands of the same shapes and transposes.

#include <algorithm>
#include <chrono>
#include <vector>

#include "common/nn/gemm.h"
#include "common/nn/tape.h"
#include "common/nn/tensor.h"

namespace srics::bench {

inline double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Median wall time in ms of `repeats` calls of f, after one warm-up call.
template <typename F>
double MedianMs(int repeats, F&& f) {
  using Clock = std::chrono::steady_clock;
  f();
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    f();
    t.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  return Median(t);
}

class GemmFloor {
 public:
  explicit GemmFloor(const std::vector<nn::GemmShape>& shapes) : shapes_(shapes) {
    for (const nn::GemmShape& s : shapes) {
      a_.push_back(s.transpose_a ? nn::Tensor::Random(s.k, s.m) : nn::Tensor::Random(s.m, s.k));
      b_.push_back(s.transpose_b ? nn::Tensor::Random(s.n, s.k) : nn::Tensor::Random(s.k, s.n));
      c_.push_back(nn::Tensor::Zero(s.m, s.n));
    }
  }
  void Run() {
    for (size_t i = 0; i < shapes_.size(); ++i) {
      nn::Gemm<float>(shapes_[i].transpose_a, shapes_[i].transpose_b, a_[i], b_[i], 0.0f, c_[i]);
    }
  }
  size_t size() const { return shapes_.size(); }
  // floating-point operations of one Run
  double Flops() const {
    double f = 0;
    for (const auto& s : shapes_) f += 2.0 * s.m * s.k * s.n;
    return f;
  }

 private:
  std::vector<nn::GemmShape> shapes_;
  std::vector<nn::Tensor> a_, b_, c_;
};

}  // namespace srics::bench
