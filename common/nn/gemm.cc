#include "common/nn/gemm.h"

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

#ifdef SRICS_WITH_ONEDNN
#include <immintrin.h>
#include <omp.h>
#include <oneapi/dnnl/dnnl.h>
#include <pthread.h>
#include <signal.h>

#include <cstdint>
#include <map>
#include <oneapi/dnnl/dnnl.hpp>
#include <tuple>
#include <vector>
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
// vs. prev_size": learners stopped by SIGINT mid-update). Every product therefore runs under a
// ScopedSignalsHeld (gemm.h): the asynchronous signals wait until it is done.
const sigset_t& AsynchronousSignals() {
  static const sigset_t set = [] {
    sigset_t s;
    sigfillset(&s);
    // faults raised by the product itself cannot wait
    for (int fault : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGTRAP, SIGABRT, SIGSYS}) sigdelset(&s, fault);
    return s;
  }();
  return set;
}
// Only the outermost guard of a thread changes its mask (two syscalls).
thread_local int signals_held_depth = 0;
thread_local sigset_t signals_saved;

void OneDnnSgemm(bool ta, bool tb, Eigen::Index m, Eigen::Index n, Eigen::Index k, const float* a, Eigen::Index lda,
                 const float* b, Eigen::Index ldb, float beta, float* c, Eigen::Index ldc) {
  // oneDNN (Debian's build) threads with OpenMP and would start a team of every core in each
  // of our threads; the learner splits its work itself (nn::WorkerPool), so one per caller.
  thread_local const bool single_threaded = (omp_set_num_threads(1), true);
  (void)single_threaded;
  dnnl_status_t status;
  {
    const ScopedSignalsHeld held;
    status = dnnl_sgemm(ta ? 'T' : 'N', tb ? 'T' : 'N', m, n, k, 1.0f, a, lda, b, ldb, beta, c, ldc);
  }
  if (status != dnnl_success) {
    throw std::runtime_error("oneDNN sgemm failed (status " + std::to_string(status) + ") on " + std::to_string(m) +
                             "x" + std::to_string(k) + " * " + std::to_string(k) + "x" + std::to_string(n));
  }
}

// ---- bfloat16 products (GemmPrecision::kBf16) ----

bool CpuAllowsBf16() {
  // oneDNN's ISA values are nested bit sets: a CPU (or cap) at AMX includes every bit of BF16
  const unsigned isa = static_cast<unsigned>(dnnl_get_effective_cpu_isa());
  const unsigned bf16 = static_cast<unsigned>(dnnl_cpu_isa_avx512_core_bf16);
  return (isa & bf16) == bf16 && __builtin_cpu_supports("avx512bf16") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512vl");
}

// Rounds `count` floats to bfloat16 (nearest even; subnormals become zero, as the instruction
// does whatever MXCSR says), 32 per instruction. Only called where
// CpuAllowsBf16(); compiled for those instructions alone so the build stays portable.
__attribute__((target("avx512f,avx512bw,avx512vl,avx512bf16"))) void RoundToBf16(const float* in, uint16_t* out,
                                                                                 size_t count) {
  size_t i = 0;
  for (; i + 32 <= count; i += 32) {
    const __m512bh packed = _mm512_cvtne2ps_pbh(_mm512_loadu_ps(in + i + 16), _mm512_loadu_ps(in + i));
    _mm512_storeu_si512(out + i, reinterpret_cast<__m512i>(packed));
  }
  for (; i < count; i += 16) {
    const size_t left = count - i < 16 ? count - i : 16;
    const __mmask16 lanes = static_cast<__mmask16>((1u << left) - 1u);
    const __m256bh half = _mm512_cvtneps_pbh(_mm512_maskz_loadu_ps(lanes, in + i));
    _mm256_mask_storeu_epi16(out + i, lanes, reinterpret_cast<__m256i>(half));
  }
}

// A stored row-major matrix (rows x cols, row stride ld) as contiguous bfloat16.
void RoundMatrix(const float* x, Eigen::Index rows, Eigen::Index cols, Eigen::Index ld, std::vector<uint16_t>* out) {
  const size_t size = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  if (out->size() < size) out->resize(size);
  if (ld == cols) {
    RoundToBf16(x, out->data(), size);
    return;
  }
  for (Eigen::Index r = 0; r < rows; ++r) RoundToBf16(x + r * ld, out->data() + r * cols, static_cast<size_t>(cols));
}

// One matmul primitive per product shape, built on first use by each thread (building one
// costs far more than running it; an update uses a few dozen shapes over and over).
struct Bf16ProductKey {
  Eigen::Index m, n, k, ldc;
  bool trans_a, trans_b;
  float beta;
  bool operator<(const Bf16ProductKey& o) const {
    return std::tie(m, n, k, ldc, trans_a, trans_b, beta) <
           std::tie(o.m, o.n, o.k, o.ldc, o.trans_a, o.trans_b, o.beta);
  }
};

struct Bf16Product {
  dnnl::matmul::primitive_desc description;
  dnnl::matmul primitive;
};

struct Bf16Thread {
  dnnl::engine engine{dnnl::engine::kind::cpu, 0};
  dnnl::stream stream{engine};
  std::map<Bf16ProductKey, Bf16Product> products;
  std::vector<uint16_t> a, b;  // the rounded operands, grown as needed
};

Bf16Product MakeBf16Product(const dnnl::engine& engine, const Bf16ProductKey& key) {
  using dt = dnnl::memory::data_type;
  using dims = dnnl::memory::dims;
  // the rounded operands keep their stored layout: op(A) is m x k, stored k x m when transposed
  const dnnl::memory::desc a({key.m, key.k}, dt::bf16, key.trans_a ? dims{1, key.m} : dims{key.k, 1});
  const dnnl::memory::desc b({key.k, key.n}, dt::bf16, key.trans_b ? dims{1, key.k} : dims{key.n, 1});
  const dnnl::memory::desc c({key.m, key.n}, dt::f32, dims{key.ldc, 1});
  dnnl::primitive_attr attr;
  if (key.beta != 0.0f) {
    dnnl::post_ops sum;
    sum.append_sum(key.beta);
    attr.set_post_ops(sum);
  }
  dnnl::matmul::primitive_desc description(dnnl::matmul::desc(a, b, c), attr, engine);
  dnnl::matmul primitive(description);
  return {std::move(description), std::move(primitive)};
}

void OneDnnBf16Gemm(bool ta, bool tb, Eigen::Index m, Eigen::Index n, Eigen::Index k, const float* a, Eigen::Index lda,
                    const float* b, Eigen::Index ldb, float beta, float* c, Eigen::Index ldc) {
  thread_local const bool single_threaded = (omp_set_num_threads(1), true);  // as OneDnnSgemm
  (void)single_threaded;
  try {
    thread_local Bf16Thread self;
    RoundMatrix(a, ta ? k : m, ta ? m : k, lda, &self.a);
    RoundMatrix(b, tb ? n : k, tb ? k : n, ldb, &self.b);
    const Bf16ProductKey key{m, n, k, ldc, ta, tb, beta};
    auto it = self.products.find(key);
    if (it == self.products.end()) {
      if (self.products.size() >= 512) self.products.clear();  // shapes of another network: start over
      it = self.products.emplace(key, MakeBf16Product(self.engine, key)).first;
    }
    const dnnl::matmul::primitive_desc& pd = it->second.description;
    dnnl::memory a_memory(pd.src_desc(), self.engine, self.a.data());
    dnnl::memory b_memory(pd.weights_desc(), self.engine, self.b.data());
    dnnl::memory c_memory(pd.dst_desc(), self.engine, c);
    const ScopedSignalsHeld held;
    it->second.primitive.execute(self.stream,
                                 {{DNNL_ARG_SRC, a_memory}, {DNNL_ARG_WEIGHTS, b_memory}, {DNNL_ARG_DST, c_memory}});
    self.stream.wait();
  } catch (const dnnl::error& e) {
    throw std::runtime_error(std::string("oneDNN bf16 product failed (") + e.what() + ") on " + std::to_string(m) +
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

thread_local GemmPrecision thread_precision = GemmPrecision::kFp32;

}  // namespace

bool Bf16ProductsAvailable() {
#ifdef SRICS_WITH_ONEDNN
  static const bool cpu_allows = CpuAllowsBf16();
  return cpu_allows && Active() == GemmBackend::kOneDnn;  // Eigen multiplies in fp32 only
#else
  return false;
#endif
}

GemmPrecision EffectiveGemmPrecision(GemmPrecision wanted) {
  return wanted == GemmPrecision::kBf16 && !Bf16ProductsAvailable() ? GemmPrecision::kFp32 : wanted;
}

GemmPrecision ThisThreadGemmPrecision() { return thread_precision; }

ScopedGemmPrecision::ScopedGemmPrecision(GemmPrecision wanted)
    : saved_(thread_precision), effective_(EffectiveGemmPrecision(wanted)) {
  thread_precision = effective_;
}

ScopedGemmPrecision::~ScopedGemmPrecision() { thread_precision = saved_; }

ScopedSignalsHeld::ScopedSignalsHeld() {
#ifdef SRICS_WITH_ONEDNN
  if (signals_held_depth++ == 0) pthread_sigmask(SIG_BLOCK, &AsynchronousSignals(), &signals_saved);
#endif
}

ScopedSignalsHeld::~ScopedSignalsHeld() {
#ifdef SRICS_WITH_ONEDNN
  if (--signals_held_depth == 0) pthread_sigmask(SIG_SETMASK, &signals_saved, nullptr);
#endif
}

bool ThisThreadHoldsSignals() {
#ifdef SRICS_WITH_ONEDNN
  sigset_t now;
  pthread_sigmask(SIG_BLOCK, nullptr, &now);
  return sigismember(&now, SIGINT) == 1 && sigismember(&now, SIGTERM) == 1;
#else
  return false;
#endif
}

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
    if (thread_precision == GemmPrecision::kBf16) {
      OneDnnBf16Gemm(trans_a, trans_b, m, n, k, a, lda, b, ldb, beta, c, ldc);
      return;
    }
    OneDnnSgemm(trans_a, trans_b, m, n, k, a, lda, b, ldb, beta, c, ldc);
    return;
  }
#endif
  EigenSgemm(trans_a, trans_b, m, n, k, a, lda, b, ldb, beta, c, ldc);
}

}  // namespace srics::nn
