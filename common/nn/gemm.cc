#include "common/nn/gemm.h"

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

#ifdef SRICS_WITH_ONEDNN
#include <omp.h>
#include <oneapi/dnnl/dnnl.h>
#include <pthread.h>
#include <signal.h>
#endif

namespace srics::nn {
namespace {

using RowMajor = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Stride = Eigen::OuterStride<>;
using ConstMap = Eigen::Map<const RowMajor, 0, Stride>;
using Map = Eigen::Map<RowMajor, 0, Stride>;

// multiply-adds below which a product runs on Eigen even when oneDNN is active (see Sgemm)
constexpr Eigen::Index kSmallestOneDnnProduct = Eigen::Index(1) << 19;

constexpr bool kHaveOneDnn =
#ifdef SRICS_WITH_ONEDNN
    true;
#else
    false;
#endif

GemmBackend BackendFromEnvironment() {
  const char* v = std::getenv("SRICS_GEMM");
  const std::string want = v ? v : "";
  if (want.empty()) return kHaveOneDnn ? GemmBackend::kOneDnn : GemmBackend::kEigen;
  if (want == "eigen") return GemmBackend::kEigen;
  if (want == "onednn") {
    if (!kHaveOneDnn) {
      throw std::invalid_argument(
          "SRICS_GEMM=onednn, but this build has no oneDNN "
          "(install libdnnl-dev and rebuild with SRICS_ONEDNN=ON)");
    }
    return GemmBackend::kOneDnn;
  }
  throw std::invalid_argument("SRICS_GEMM='" + want + "': expected eigen or onednn");
}

// -1: not chosen yet
std::atomic<int> active_backend{-1};
std::mutex choose_mutex;

GemmBackend Active() {
  int b = active_backend.load(std::memory_order_acquire);
  if (b < 0) {
    std::lock_guard<std::mutex> lock(choose_mutex);
    b = active_backend.load(std::memory_order_relaxed);
    if (b < 0) {
      b = static_cast<int>(BackendFromEnvironment());
      active_backend.store(b, std::memory_order_release);
    }
  }
  return static_cast<GemmBackend>(b);
}

void EigenSgemm(bool ta, bool tb, Eigen::Index m, Eigen::Index n, Eigen::Index k, const float* a, Eigen::Index lda,
                const float* b, Eigen::Index ldb, float beta, float* c, Eigen::Index ldc) {
  const ConstMap A(a, ta ? k : m, ta ? m : k, Stride(lda));
  const ConstMap B(b, tb ? n : k, tb ? k : n, Stride(ldb));
  EigenGemm(ta, tb, A, B, beta, Map(c, m, n, Stride(ldc)));
}

#ifdef SRICS_WITH_ONEDNN
// oneDNN's AVX-512 f32 GEMM kernels (2.6.3, Debian 12's) point the stack pointer into a heap
// buffer while they run (oneDNN issue 4845, fixed in 3.11.2): a signal handled in this thread
// meanwhile pushes its frame onto the heap, which malloc finds corrupted later ("corrupted size
// vs. prev_size": learners stopped by SIGINT mid-update). The asynchronous signals wait until
// the product is done; one sent to the process goes to another thread. Two syscalls per
// product, each of at least 2^19 multiply-adds (kSmallestOneDnnProduct): under 1% of it.
class AsynchronousSignalsBlocked {
 public:
  AsynchronousSignalsBlocked() { pthread_sigmask(SIG_BLOCK, &Set(), &saved_); }
  ~AsynchronousSignalsBlocked() { pthread_sigmask(SIG_SETMASK, &saved_, nullptr); }
  AsynchronousSignalsBlocked(const AsynchronousSignalsBlocked&) = delete;
  AsynchronousSignalsBlocked& operator=(const AsynchronousSignalsBlocked&) = delete;

 private:
  static const sigset_t& Set() {
    static const sigset_t set = [] {
      sigset_t s;
      sigfillset(&s);
      // faults raised by the product itself cannot wait
      for (int fault : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGTRAP, SIGABRT, SIGSYS}) sigdelset(&s, fault);
      return s;
    }();
    return set;
  }
  sigset_t saved_;
};

void OneDnnSgemm(bool ta, bool tb, Eigen::Index m, Eigen::Index n, Eigen::Index k, const float* a, Eigen::Index lda,
                 const float* b, Eigen::Index ldb, float beta, float* c, Eigen::Index ldc) {
  // oneDNN (Debian's build) threads with OpenMP and would start a team of every core in each
  // of our threads; the learner splits its work itself (nn::WorkerPool), so one per caller.
  thread_local const bool single_threaded = (omp_set_num_threads(1), true);
  (void)single_threaded;
  dnnl_status_t status;
  {
    const AsynchronousSignalsBlocked blocked;
    status = dnnl_sgemm(ta ? 'T' : 'N', tb ? 'T' : 'N', m, n, k, 1.0f, a, lda, b, ldb, beta, c, ldc);
  }
  if (status != dnnl_success) {
    throw std::runtime_error("oneDNN sgemm failed (status " + std::to_string(status) + ") on " + std::to_string(m) +
                             "x" + std::to_string(k) + " * " + std::to_string(k) + "x" + std::to_string(n));
  }
}

std::string IsaName(dnnl_cpu_isa_t isa) {
  switch (isa) {
    case dnnl_cpu_isa_sse41: return "sse41";
    case dnnl_cpu_isa_avx: return "avx";
    case dnnl_cpu_isa_avx2: return "avx2";
    case dnnl_cpu_isa_avx2_vnni: return "avx2_vnni";
    case dnnl_cpu_isa_avx512_core: return "avx512_core";
    case dnnl_cpu_isa_avx512_core_vnni: return "avx512_core_vnni";
    case dnnl_cpu_isa_avx512_core_bf16: return "avx512_core_bf16";
    case dnnl_cpu_isa_avx512_core_amx: return "avx512_core_amx";
    default: return "isa " + std::to_string(static_cast<int>(isa));
  }
}
#endif

}  // namespace

bool GemmBackendAvailable(GemmBackend backend) { return backend == GemmBackend::kEigen || kHaveOneDnn; }

GemmBackend ActiveGemmBackend() { return Active(); }

void SetGemmBackend(GemmBackend backend) {
  if (!GemmBackendAvailable(backend)) {
    throw std::invalid_argument("this build has no oneDNN (install libdnnl-dev, SRICS_ONEDNN=ON)");
  }
  std::lock_guard<std::mutex> lock(choose_mutex);
  active_backend.store(static_cast<int>(backend), std::memory_order_release);
}

std::string GemmBackendDescription() {
  if (Active() == GemmBackend::kEigen) return "eigen";
#ifdef SRICS_WITH_ONEDNN
  return "onednn (" + IsaName(dnnl_get_effective_cpu_isa()) + ")";
#else
  return "onednn";
#endif
}

void Sgemm(bool trans_a, bool trans_b, Eigen::Index m, Eigen::Index n, Eigen::Index k, const float* a, Eigen::Index lda,
           const float* b, Eigen::Index ldb, float beta, float* c, Eigen::Index ldc) {
  if (m == 0 || n == 0) return;
#ifdef SRICS_WITH_ONEDNN
  // oneDNN allocates its packing buffers on every call (posix_memalign): small products, such
  // as the actors' single-observation path, which must not allocate, stay on Eigen (which
  // blocks them on the stack); they are a negligible share of an update's time
  if (Active() == GemmBackend::kOneDnn && k > 0 && m * n * k >= kSmallestOneDnnProduct) {
    OneDnnSgemm(trans_a, trans_b, m, n, k, a, lda, b, ldb, beta, c, ldc);
    return;
  }
#endif
  EigenSgemm(trans_a, trans_b, m, n, k, a, lda, b, ldb, beta, c, ldc);
}

}  // namespace srics::nn
