#pragma once
// The one place where float matrices are multiplied. With oneDNN in the build (the default when
// Debian's libdnnl-dev is installed), products run on oneDNN's sgemm, whose JIT kernels are
// chosen at run time for the CPU at hand (AVX2, AVX-512, ...); otherwise, or when the
// environment says SRICS_GEMM=eigen, on Eigen's own GEMM, compiled for the build's
// instruction set. Both give the same products up to float summation order.
//
// oneDNN measured 1.3-1.8x faster than Eigen on the skinny products of the networks (1280x80
// times 80x80, 256x128 times 128x128, ...) on an AVX2 machine: tests/bench/nn, docs/results.md.
// oneDNN's own cap on instruction sets (DNNL_MAX_CPU_ISA=AVX2, SSE41, ...) selects its other
// kernels; the tests run under several caps.

#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "common/nn/tensor.h"

namespace srics::nn {

enum class GemmBackend { kEigen, kOneDnn };

// Whether this build can multiply with `backend` (kEigen always can).
bool GemmBackendAvailable(GemmBackend backend);

// The backend products use now: oneDNN when built in, unless SRICS_GEMM=eigen was set in the
// environment at the first product (SRICS_GEMM=onednn without oneDNN in the build is an error).
GemmBackend ActiveGemmBackend();

// Switches the backend for the rest of the process (tests and benchmarks compare the two in
// one process). Throws std::invalid_argument for a backend the build lacks. Not to be called
// while another thread multiplies.
void SetGemmBackend(GemmBackend backend);

// "eigen" or "onednn"; with oneDNN, also the instruction set its kernels use, e.g.
// "onednn (avx2)".
std::string GemmBackendDescription();

// The precision of oneDNN's products on the calling thread. kBf16 rounds both operands to
// bfloat16 (8 bits of mantissa, round to nearest even, subnormals to zero) and accumulates in
// fp32 into the fp32 result (0.77-0.80x of the SAC update's CPU time on the AVX-512 BF16 EPYC,
// docs/benchmarks.md). Callers keep weights, gradients and optimizer state in fp32; the
// gradients are computed from the rounded products.
// Products that run on Eigen (the small ones, or the Eigen backend) stay fp32.
enum class GemmPrecision { kFp32, kBf16 };

// Whether kBf16 runs here: oneDNN in the build and the active backend, the CPU has AVX-512
// BF16 (AMX CPUs have it too), and oneDNN's instruction-set cap (DNNL_MAX_CPU_ISA) allows it.
bool Bf16ProductsAvailable();

// The precision that runs when `wanted` is asked for: kBf16 only where Bf16ProductsAvailable().
GemmPrecision EffectiveGemmPrecision(GemmPrecision wanted);

// The calling thread's precision (kFp32 unless a ScopedGemmPrecision says otherwise).
GemmPrecision ThisThreadGemmPrecision();

// Sets the calling thread's precision for the guard's lifetime, then restores the one before.
// kBf16 where Bf16ProductsAvailable() is false gives kFp32: effective() says which.
class ScopedGemmPrecision {
 public:
  explicit ScopedGemmPrecision(GemmPrecision wanted);
  ~ScopedGemmPrecision();
  ScopedGemmPrecision(const ScopedGemmPrecision&) = delete;
  ScopedGemmPrecision& operator=(const ScopedGemmPrecision&) = delete;
  GemmPrecision effective() const { return effective_; }

 private:
  GemmPrecision saved_;
  GemmPrecision effective_;
};

// Holds back the asynchronous signals (SIGINT, SIGTERM, ...; not the faults) on the calling
// thread while it lives: one sent to the process goes to another thread meanwhile, one sent to
// this thread waits. Nestable. Every oneDNN product takes it (oneDNN 2.6's kernels run with the
// stack pointer in a heap buffer, gemm.cc); a caller that runs many products in a row, such as
// one pass of the SAC update, takes it once around them: two syscalls per pass instead of two
// per product (about 2% of a batch-256 update). A no-op in a build without oneDNN.
class ScopedSignalsHeld {
 public:
  ScopedSignalsHeld();
  ~ScopedSignalsHeld();
  ScopedSignalsHeld(const ScopedSignalsHeld&) = delete;
  ScopedSignalsHeld& operator=(const ScopedSignalsHeld&) = delete;
};

// Whether the calling thread's signal mask holds SIGINT and SIGTERM back now (tests).
bool ThisThreadHoldsSignals();

// C = op(A) * op(B) + beta * C for row-major float matrices, op(X) = X^T when trans_x is set.
// op(A) is m x k, op(B) is k x n, C is m x n; lda, ldb, ldc are the row strides as stored.
// beta 0 overwrites C (whatever it held, NaN included). Runs on the calling thread only.
// Products of fewer than 2^19 multiply-adds run on Eigen whatever the backend: oneDNN
// allocates heap buffers on every call, and the actors' action path must not allocate. On
// oneDNN, in the calling thread's precision (ThisThreadGemmPrecision).
void Sgemm(bool trans_a, bool trans_b, Eigen::Index m, Eigen::Index n, Eigen::Index k, const float* a, Eigen::Index lda,
           const float* b, Eigen::Index ldb, float beta, float* c, Eigen::Index ldc);

// c = op(a) * op(b) + beta * c on Eigen's own product, any Eigen operands; c has the product's
// shape. Eigen's path of Sgemm and of Gemm for doubles.
template <typename A, typename B, typename C>
void EigenGemm(bool trans_a, bool trans_b, const A& a, const B& b, typename std::decay_t<C>::Scalar beta, C&& c) {
  using T = typename std::decay_t<C>::Scalar;
  if (beta == T(0))
    c.setZero();  // beta 0 ignores what c held (BLAS convention), NaN included
  else if (beta != T(1))
    c *= beta;
  if (!trans_a && !trans_b)
    c.noalias() += a * b;
  else if (trans_a && !trans_b)
    c.noalias() += a.transpose() * b;
  else if (!trans_a && trans_b)
    c.noalias() += a * b.transpose();
  else
    c.noalias() += a.transpose() * b.transpose();
}

// c = op(a) * op(b) + beta * c for tensors: floats through Sgemm, other scalars (the double
// gradient checks) through Eigen. beta 0 resizes c to the product's shape first; otherwise c
// must have it.
template <typename T>
void Gemm(bool trans_a, bool trans_b, const Eigen::Ref<const Matrix<T>>& a, const Eigen::Ref<const Matrix<T>>& b,
          T beta, Matrix<T>& c) {
  const Eigen::Index m = trans_a ? a.cols() : a.rows();
  const Eigen::Index k = trans_a ? a.rows() : a.cols();
  const Eigen::Index n = trans_b ? b.rows() : b.cols();
  if ((trans_b ? b.cols() : b.rows()) != k) throw std::invalid_argument("nn::Gemm: inner sizes differ");
  if (beta == T(0)) {
    c.resize(m, n);
  } else if (c.rows() != m || c.cols() != n) {
    throw std::invalid_argument("nn::Gemm: accumulator has the wrong shape");
  }
  if constexpr (std::is_same_v<T, float>) {
    Sgemm(trans_a, trans_b, m, n, k, a.data(), a.outerStride(), b.data(), b.outerStride(), beta, c.data(), c.cols());
  } else {
    EigenGemm(trans_a, trans_b, a, b, beta, c);
  }
}

}  // namespace srics::nn
