// Products of every backend against a double-precision loop, in every transposition, with
// strides and both betas. CMake runs this file three times: as is (oneDNN's best kernels for
// this CPU) and under DNNL_MAX_CPU_ISA=AVX2 and =SSE41 (its other kernels), so that on an
// AVX-512 machine the AVX2 path is checked too.
#include "common/nn/gemm.h"

#include <gtest/gtest.h>

#include <dirent.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace srics::nn {
namespace {

struct Shape {
  Eigen::Index m, k, n;
};

// shapes of the networks (entity tokens x embedding, MLP layers, their backward products) and
// odd ones that leave remainders in every kernel tile
const std::vector<Shape> kShapes = {{1, 1, 1},       {3, 7, 5},      {17, 33, 9},    {1280, 80, 80},  {1280, 15, 80},
                                    {256, 128, 128}, {80, 1280, 80}, {257, 129, 65}, {2048, 208, 128}};

std::vector<GemmBackend> Backends() {
  std::vector<GemmBackend> out = {GemmBackend::kEigen};
  if (GemmBackendAvailable(GemmBackend::kOneDnn)) out.push_back(GemmBackend::kOneDnn);
  return out;
}

class BackendGuard {
 public:
  BackendGuard() : saved_(ActiveGemmBackend()) {}
  ~BackendGuard() { SetGemmBackend(saved_); }

 private:
  GemmBackend saved_;
};

Matrix<float> Random(Eigen::Index rows, Eigen::Index cols, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Matrix<float> x(rows, cols);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = u(rng);
  return x;
}

// op(a)(i, p) read through the stored matrix
double At(const Eigen::Ref<const Matrix<float>>& x, bool trans, Eigen::Index i, Eigen::Index p) {
  return trans ? x(p, i) : x(i, p);
}

TEST(GemmTest, EveryBackendMatchesADoubleLoopInEveryTranspositionWithBothBetas) {
  BackendGuard guard;
  std::mt19937 rng(7);
  for (GemmBackend backend : Backends()) {
    SetGemmBackend(backend);
    for (const Shape& s : kShapes) {
      for (int t = 0; t < 4; ++t) {
        const bool ta = t & 1, tb = t & 2;
        const Matrix<float> a = ta ? Random(s.k, s.m, rng) : Random(s.m, s.k, rng);
        const Matrix<float> b = tb ? Random(s.n, s.k, rng) : Random(s.k, s.n, rng);
        const Matrix<float> c0 = Random(s.m, s.n, rng);
        // beta 0 must ignore what C holds, NaN included
        Matrix<float> c = Matrix<float>::Constant(s.m, s.n, std::numeric_limits<float>::quiet_NaN());
        Gemm<float>(ta, tb, a, b, 0.0f, c);
        Matrix<float> acc = c0;
        Gemm<float>(ta, tb, a, b, 1.0f, acc);
        ASSERT_EQ(c.rows(), s.m);
        ASSERT_EQ(c.cols(), s.n);
        double worst = 0;
        for (Eigen::Index i = 0; i < s.m; ++i) {
          for (Eigen::Index j = 0; j < s.n; ++j) {
            double want = 0;
            for (Eigen::Index p = 0; p < s.k; ++p) want += At(a, ta, i, p) * At(b, tb, p, j);
            worst = std::max(worst, std::abs(c(i, j) - want));
            worst = std::max(worst, std::abs(acc(i, j) - (want + c0(i, j))));
          }
        }
        // float rounding of k products of numbers under 1: a few ulps times sqrt(k)
        EXPECT_LT(worst, 2e-6 * std::sqrt(double(s.k)) * 8)
            << GemmBackendDescription() << " " << s.m << "x" << s.k << "x" << s.n << " ta " << ta << " tb " << tb;
      }
    }
  }
}

TEST(GemmTest, ReadsOperandsThroughTheirRowStride) {
  BackendGuard guard;
  std::mt19937 rng(3);
  const Matrix<float> big_a = Random(40, 50, rng), big_b = Random(60, 30, rng);
  const auto a = big_a.block(2, 5, 21, 13);  // 21 x 13, row stride 50
  const auto b = big_b.block(7, 1, 13, 11);  // 13 x 11, row stride 30
  const Matrix<float> want = Matrix<float>(a) * Matrix<float>(b);
  for (GemmBackend backend : Backends()) {
    SetGemmBackend(backend);
    Matrix<float> c;
    Gemm<float>(false, false, a, b, 0.0f, c);
    EXPECT_LT((c - want).cwiseAbs().maxCoeff(), 1e-5f) << GemmBackendDescription();
  }
}

TEST(GemmTest, DoublesGoThroughEigenExactlyAsItsOwnProduct) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01;
  Matrix<double> a(9, 4), b(9, 6);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = n01(rng);
  for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = n01(rng);
  Matrix<double> c;
  Gemm<double>(true, false, a, b, 0.0, c);
  const Matrix<double> want = a.transpose() * b;
  EXPECT_LT((c - want).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(GemmTest, RefusesMismatchedShapes) {
  Matrix<float> a(3, 4), b(5, 2), c(3, 2);
  a.setOnes();
  b.setOnes();
  EXPECT_THROW(Gemm<float>(false, false, a, b, 0.0f, c), std::invalid_argument);
  Matrix<float> b2(4, 2), wrong(2, 2);
  b2.setOnes();
  EXPECT_THROW(Gemm<float>(false, false, a, b2, 1.0f, wrong), std::invalid_argument);
}

int ThreadCount() {
  int n = 0;
  if (DIR* d = opendir("/proc/self/task")) {
    while (dirent* e = readdir(d)) n += e->d_name[0] != '.';
    closedir(d);
  }
  return n;
}

// oneDNN threads with OpenMP, which by default starts a team of every core: the learner's own
// worker threads would then each start one more (oversubscribing the machine)
TEST(GemmTest, ProductsStartNoThreadsOfTheirOwn) {
  BackendGuard guard;
  std::mt19937 rng(11);
  const Matrix<float> a = Random(512, 512, rng), b = Random(512, 512, rng);
  for (GemmBackend backend : Backends()) {
    SetGemmBackend(backend);
    const int before = ThreadCount();
    Matrix<float> c;
    Gemm<float>(false, false, a, b, 0.0f, c);
    std::thread other([&] {
      Matrix<float> d;
      Gemm<float>(false, false, a, b, 0.0f, d);
    });
    other.join();
    EXPECT_EQ(ThreadCount(), before) << GemmBackendDescription();
  }
}

// oneDNN's f32 GEMM kernels for AVX-512 point the stack pointer into a heap buffer while they
// run (oneDNN issue 4845, fixed in 3.11.2; Debian 12 ships 2.6.3): a signal handled in that
// thread meanwhile pushes its frame onto the heap. Our processes handle SIGINT and SIGTERM (the
// shutdown) and the launcher SIGCHLD: a learner stopped during an update, or a run in process
// whose child exits, aborted with "corrupted size vs. prev_size" (2026-12-02: a campaign HAC run
// on Ctrl-C; the foreign-participant system test's learner in 3 of 21 runs). Here a thread
// multiplies while another sends it a handled signal every few microseconds; the heap is then
// exercised. The child must exit normally (before the fix: SIGABRT from malloc, or SIGSEGV).
// The death test's child: products in one thread, a handled signal to it every 20 us from
// this one, then the heap exercised; exits 0 if nothing broke.
[[noreturn]] void MultiplyUnderSignals() {
  SetGemmBackend(GemmBackend::kOneDnn);
  struct sigaction action = {};
  action.sa_handler = [](int) {};
  sigemptyset(&action.sa_mask);
  sigaction(SIGUSR1, &action, nullptr);
  std::mt19937 rng(3);
  const Matrix<float> a = Random(256, 128, rng), b = Random(128, 256, rng);
  std::atomic<bool> done{false};
  std::thread worker([&] {
    Matrix<float> c;
    for (int i = 0; i < 1500; ++i) {
      Gemm<float>(false, false, a, b, 0.0f, c);
      std::vector<float> churn(1000 + i % 7 * 100, 1.0f);  // the heap in use between products
    }
    done = true;
  });
  const pthread_t target = worker.native_handle();
  while (!done) {
    pthread_kill(target, SIGUSR1);
    std::this_thread::sleep_for(std::chrono::microseconds(20));
  }
  worker.join();
  std::vector<std::vector<float>> blocks;
  for (int i = 0; i < 1000; ++i) blocks.emplace_back(static_cast<size_t>(i) * 37 + 1, 0.5f);
  blocks.clear();
  std::exit(0);
}

TEST(GemmDeathTest, SignalsDuringProductsLeaveTheHeapIntact) {
  if (!GemmBackendAvailable(GemmBackend::kOneDnn)) GTEST_SKIP() << "no oneDNN in this build";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(MultiplyUnderSignals(), ::testing::ExitedWithCode(0), "");
}

// A pass of many products (the SAC update's) holds the signals once: nested guards change the
// thread's mask only at the outermost, which restores the mask as it found it (a signal the
// caller had blocked stays blocked); the products inside take no guard of their own.
TEST(GemmTest, NestedSignalGuardsHoldUntilTheOutermostEndsAndRestoreTheMask) {
  if (!GemmBackendAvailable(GemmBackend::kOneDnn)) GTEST_SKIP() << "no oneDNN in this build";
  BackendGuard guard;
  SetGemmBackend(GemmBackend::kOneDnn);
  std::mt19937 rng(5);
  const Matrix<float> a = Random(256, 128, rng), b = Random(128, 256, rng);
  EXPECT_FALSE(ThisThreadHoldsSignals());
  {
    const ScopedSignalsHeld outer;
    EXPECT_TRUE(ThisThreadHoldsSignals());
    {
      const ScopedSignalsHeld inner;
      Matrix<float> c;
      Gemm<float>(false, false, a, b, 0.0f, c);  // takes and releases its own guard inside
      EXPECT_TRUE(ThisThreadHoldsSignals());
    }
    EXPECT_TRUE(ThisThreadHoldsSignals());  // the inner guard left the outer one's mask
  }
  EXPECT_FALSE(ThisThreadHoldsSignals());
  sigset_t usr1, before, after;
  sigemptyset(&usr1);
  sigaddset(&usr1, SIGUSR1);
  pthread_sigmask(SIG_BLOCK, &usr1, &before);
  { const ScopedSignalsHeld held; }
  pthread_sigmask(SIG_BLOCK, nullptr, &after);
  EXPECT_EQ(sigismember(&after, SIGUSR1), 1);  // the caller's own block survives
  EXPECT_EQ(sigismember(&after, SIGINT), 0);
  pthread_sigmask(SIG_SETMASK, &before, nullptr);
}

TEST(GemmTest, DescribesTheBackendAndTheInstructionSetInUse) {
  BackendGuard guard;
  SetGemmBackend(GemmBackend::kEigen);
  EXPECT_EQ(GemmBackendDescription(), "eigen");
  if (!GemmBackendAvailable(GemmBackend::kOneDnn)) {
    EXPECT_THROW(SetGemmBackend(GemmBackend::kOneDnn), std::invalid_argument);
    GTEST_SKIP() << "this build has no oneDNN";
  }
  SetGemmBackend(GemmBackend::kOneDnn);
  const std::string d = GemmBackendDescription();
  EXPECT_EQ(d.rfind("onednn (", 0), 0u) << d;
  // under a cap, the kernels in use are the capped ones (DNNL_MAX_CPU_ISA is oneDNN's own)
  if (const char* cap = std::getenv("DNNL_MAX_CPU_ISA")) {
    std::string want = cap;
    for (char& ch : want) ch = static_cast<char>(std::tolower(ch));
    EXPECT_EQ(d, "onednn (" + want + ")");
  }
}

// ---- bfloat16 products ----

// oneDNN's instruction-set cap, if any (it reads either variable, in any case): "" when none.
std::string IsaCap() {
  for (const char* name : {"ONEDNN_MAX_CPU_ISA", "DNNL_MAX_CPU_ISA"}) {
    if (const char* cap = std::getenv(name)) {
      std::string upper(cap);
      for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      return upper;
    }
  }
  return "";
}

TEST(GemmBf16Test, IsOfferedExactlyWhereTheCpuAndOneDnnsCapAllowIt) {
  if (!GemmBackendAvailable(GemmBackend::kOneDnn)) {
    EXPECT_FALSE(Bf16ProductsAvailable());
    return;
  }
  const std::string cap = IsaCap();
  if (cap == "AVX2" || cap == "SSE41") {
    EXPECT_FALSE(Bf16ProductsAvailable()) << "under the cap " << cap;
  } else if (cap.empty()) {
    EXPECT_EQ(Bf16ProductsAvailable(), __builtin_cpu_supports("avx512bf16") != 0);
  } else if (Bf16ProductsAvailable()) {
    EXPECT_TRUE(__builtin_cpu_supports("avx512bf16"));  // another cap: never beyond the CPU
  }
  {
    BackendGuard guard;
    SetGemmBackend(GemmBackend::kEigen);  // Eigen multiplies in fp32 only
    EXPECT_FALSE(Bf16ProductsAvailable());
    EXPECT_EQ(ScopedGemmPrecision(GemmPrecision::kBf16).effective(), GemmPrecision::kFp32);
  }
  const ScopedGemmPrecision scoped(GemmPrecision::kBf16);
  EXPECT_EQ(scoped.effective(), Bf16ProductsAvailable() ? GemmPrecision::kBf16 : GemmPrecision::kFp32);
  EXPECT_EQ(ThisThreadGemmPrecision(), scoped.effective());
}

// Where bf16 is not available the request falls back to fp32: the very same products.
TEST(GemmBf16Test, WithoutTheInstructionsARequestGivesTheFp32ProductsBitForBit) {
  if (Bf16ProductsAvailable()) GTEST_SKIP() << "this CPU multiplies in bf16 (the caps' runs check the fallback)";
  BackendGuard guard;
  std::mt19937 rng(13);
  const Matrix<float> a = Random(256, 128, rng), b = Random(128, 128, rng);
  for (GemmBackend backend : Backends()) {
    SetGemmBackend(backend);
    Matrix<float> fp32, requested;
    Gemm<float>(false, false, a, b, 0.0f, fp32);
    {
      const ScopedGemmPrecision scoped(GemmPrecision::kBf16);
      Gemm<float>(false, false, a, b, 0.0f, requested);
    }
    EXPECT_EQ(requested, fp32) << GemmBackendDescription();
  }
}

// Every transposition, both betas, a row stride: within bfloat16's rounding of the operands
// (each off by at most 2^-8 of itself: a product term by about 2^-7 of |a||b|), and
// really rounded (an fp32 product would be ~1000 times closer).
TEST(GemmBf16Test, ProductsAreWithinBfloat16RoundingOfTheExactOnes) {
  if (!Bf16ProductsAvailable()) GTEST_SKIP() << "no bf16 products on this CPU or under this cap";
  BackendGuard guard;
  SetGemmBackend(GemmBackend::kOneDnn);
  const ScopedGemmPrecision scoped(GemmPrecision::kBf16);
  std::mt19937 rng(17);
  const std::vector<Shape> shapes = {{1280, 80, 80}, {256, 128, 128}, {80, 1280, 80}, {257, 129, 65}};
  for (const Shape& s : shapes) {
    for (int t = 0; t < 4; ++t) {
      const bool ta = t & 1, tb = t & 2;
      const Matrix<float> a = ta ? Random(s.k, s.m, rng) : Random(s.m, s.k, rng);
      const Matrix<float> big_b = tb ? Random(s.n, s.k + 3, rng) : Random(s.k, s.n + 3, rng);
      const auto b = tb ? big_b.block(0, 2, s.n, s.k) : big_b.block(0, 2, s.k, s.n);  // row stride + 3
      const Matrix<float> c0 = Random(s.m, s.n, rng);
      Matrix<float> c, acc = c0;
      Gemm<float>(ta, tb, a, b, 0.0f, c);
      Gemm<float>(ta, tb, a, b, 1.0f, acc);
      double worst_share = 0, largest_error = 0;
      for (Eigen::Index i = 0; i < s.m; ++i) {
        for (Eigen::Index j = 0; j < s.n; ++j) {
          double want = 0, magnitude = 0;
          for (Eigen::Index p = 0; p < s.k; ++p) {
            want += At(a, ta, i, p) * At(b, tb, p, j);
            magnitude += std::abs(At(a, ta, i, p) * At(b, tb, p, j));
          }
          const double error = std::max(std::abs(c(i, j) - want), std::abs(acc(i, j) - (want + c0(i, j))));
          largest_error = std::max(largest_error, error);
          worst_share = std::max(worst_share, error / magnitude);
        }
      }
      const std::string where = std::to_string(s.m) + "x" + std::to_string(s.k) + "x" + std::to_string(s.n) + " ta " +
                                std::to_string(ta) + " tb " + std::to_string(tb);
      EXPECT_LT(worst_share, std::ldexp(1.0, -7)) << where;
      EXPECT_GT(largest_error, 1e-4) << where << ": no bf16 rounding visible";
    }
  }
}

// Values bfloat16 holds exactly multiply exactly; others round to the nearest bfloat16 (7
// mantissa bits: 1 + 3 * 2^-9 up to 1 + 2^-7, where truncation gives 1), a tie to the even one
// (1 + 2^-7 + 2^-8 up to 1 + 2^-6, where truncation gives 1 + 2^-7).
TEST(GemmBf16Test, RoundsEachOperandToTheNearestBfloat16) {
  if (!Bf16ProductsAvailable()) GTEST_SKIP() << "no bf16 products on this CPU or under this cap";
  BackendGuard guard;
  SetGemmBackend(GemmBackend::kOneDnn);
  std::mt19937 rng(19);
  std::uniform_int_distribution<int> small(-8, 8);
  Matrix<float> a(128, 128), b(128, 128);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = std::ldexp(float(small(rng)), -3);
  for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = float(small(rng));
  Matrix<float> fp32, bf16;
  Gemm<float>(false, false, a, b, 0.0f, fp32);
  {
    const ScopedGemmPrecision scoped(GemmPrecision::kBf16);
    Gemm<float>(false, false, a, b, 0.0f, bf16);
    EXPECT_EQ(bf16, fp32);  // exact operands, sums of integers / 8: exact in both
    Matrix<float> unit, product;
    unit.setIdentity(128, 128);
    const Matrix<float> above_half = Matrix<float>::Constant(128, 128, 1.0f + 3.0f * std::ldexp(1.0f, -9));
    Gemm<float>(false, false, above_half, unit, 0.0f, product);
    EXPECT_EQ(product, Matrix<float>::Constant(128, 128, 1.0f + std::ldexp(1.0f, -7)));
    const Matrix<float> tie = Matrix<float>::Constant(128, 128, 1.0f + std::ldexp(1.0f, -7) + std::ldexp(1.0f, -8));
    Gemm<float>(false, false, tie, unit, 0.0f, product);
    EXPECT_EQ(product, Matrix<float>::Constant(128, 128, 1.0f + std::ldexp(1.0f, -6)));
  }
}

// The precision is the calling thread's: another thread's products stay fp32.
TEST(GemmBf16Test, APrecisionSetInOneThreadLeavesTheOthersAtFp32) {
  BackendGuard guard;
  std::mt19937 rng(23);
  const Matrix<float> a = Random(256, 128, rng), b = Random(128, 128, rng);
  Matrix<float> fp32;
  Gemm<float>(false, false, a, b, 0.0f, fp32);
  const ScopedGemmPrecision scoped(GemmPrecision::kBf16);
  Matrix<float> other;
  GemmPrecision seen = GemmPrecision::kBf16;
  std::thread t([&] {
    seen = ThisThreadGemmPrecision();
    Gemm<float>(false, false, a, b, 0.0f, other);
  });
  t.join();
  EXPECT_EQ(seen, GemmPrecision::kFp32);
  EXPECT_EQ(other, fp32);
}

}  // namespace
}  // namespace srics::nn
