// ./tests/bench.sh nn: forward + backward of the SAC attention policy and one Q network
// against the "GEMM floor" (the very matrix products the tape executed, as bare Eigen
// products of the same shapes and storage order, through the same GEMM), the single-observation
// action time, and the products of these networks on each GEMM backend (common/nn/gemm.h):
// GFLOP/s per distinct shape, Eigen against oneDNN. One thread; medians over repeats. Last
// line: one JSON object.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "common/nn/gemm.h"
#include "common/nn/tape.h"
#include "common/rl/networks.h"
#include "tests/bench/bench_util.h"
#include "tests/common/rl/network_configs.h"

namespace {

using srics::nn::GemmShape;
using srics::nn::Matrix;
using srics::nn::Rng;
using srics::nn::Tape;
using srics::nn::Tensor;
using Clock = std::chrono::steady_clock;
using srics::bench::GemmFloor;
using srics::bench::MedianMs;
using srics::rl::testing::PaperNetworkConfig;

struct Case {
  int batch, entities;
  double policy_ms, q_ms, floor_ms;
  std::vector<GemmShape> shapes;
};

Case RunCase(int batch, int entities, int repeats) {
  Rng rng(1);
  const auto config = PaperNetworkConfig(entities);
  srics::rl::PolicyNetwork<float> policy("policy", config, rng);
  srics::rl::QNetwork<float> q("q1", config, rng);
  std::vector<Tensor> sets;
  for (int b = 0; b < batch; ++b) sets.push_back(Tensor::Random(entities, config.entity_dim));
  const auto data = srics::rl::PackEntities(sets, Tensor(Tensor::Random(batch, config.goal_dim)));
  const Tensor eps = srics::nn::RandomNormal<float>(batch, 2, rng);
  const Tensor actions = Tensor::Random(batch, 2);
  const Tensor target = Tensor::Random(batch, 1);
  Tape<float> tape;
  auto policy_step = [&] {
    tape.Reset();
    auto out = policy.Forward(tape, data, eps);
    tape.Backward(tape.Mean(tape.Add(tape.Sum(out.action, 1), out.log_prob)));
  };
  auto q_step = [&] {
    tape.Reset();
    auto value = q.Forward(tape, data, tape.Constant(actions));
    tape.Backward(tape.Mean(tape.Square(tape.Sub(value, tape.Constant(target)))));
  };
  std::vector<GemmShape> shapes;
  tape.set_gemm_log(&shapes);
  policy_step();
  q_step();
  tape.set_gemm_log(nullptr);
  GemmFloor floor(shapes);
  Case c{batch, entities, 0, 0, 0, shapes};
  c.policy_ms = MedianMs(repeats, policy_step);
  c.q_ms = MedianMs(repeats, q_step);
  c.floor_ms = MedianMs(repeats, [&] { floor.Run(); });
  return c;
}

double ActMicros(int entities) {
  Rng rng(2);
  const auto config = PaperNetworkConfig(entities);
  srics::rl::PolicyNetwork<float> policy("policy", config, rng);
  const Tensor ents = Tensor::Random(entities, config.entity_dim);
  const Tensor goal = Tensor::Random(1, config.goal_dim);
  float sink = 0;
  const int calls = 2000;
  const double ms = MedianMs(15, [&] {
    for (int i = 0; i < calls; ++i) sink += policy.Act(ents, goal, false, rng)(0, 0);
  });
  if (sink == 12345.f) std::printf(" ");
  return ms * 1000.0 / calls;
}

// GFLOP/s of one product shape on the backend in use (median of repeats)
double ShapeGflops(const GemmShape& s) {
  const Tensor a = s.transpose_a ? Tensor::Random(s.k, s.m) : Tensor::Random(s.m, s.k);
  const Tensor b = s.transpose_b ? Tensor::Random(s.n, s.k) : Tensor::Random(s.k, s.n);
  Tensor c;
  const double flop = 2.0 * s.m * s.k * s.n;
  const int calls = std::max(1, static_cast<int>(2e8 / flop));
  const double ms = MedianMs(9, [&] {
    for (int i = 0; i < calls; ++i) srics::nn::Gemm<float>(s.transpose_a, s.transpose_b, a, b, 0.0f, c);
  });
  return flop * calls / (ms * 1e6);
}

struct ShapeRate {
  GemmShape shape;
  double eigen = 0, onednn = 0;
};

// the distinct product shapes of a case, each on Eigen and (when built in) on oneDNN
std::vector<ShapeRate> ShapeRates(const std::vector<GemmShape>& shapes) {
  std::vector<ShapeRate> out;
  for (const GemmShape& s : shapes) {
    const bool seen = std::any_of(out.begin(), out.end(), [&](const ShapeRate& r) {
      return r.shape.m == s.m && r.shape.k == s.k && r.shape.n == s.n && r.shape.transpose_a == s.transpose_a &&
             r.shape.transpose_b == s.transpose_b;
    });
    if (!seen) out.push_back({s});
  }
  const srics::nn::GemmBackend active = srics::nn::ActiveGemmBackend();
  for (ShapeRate& r : out) {
    srics::nn::SetGemmBackend(srics::nn::GemmBackend::kEigen);
    r.eigen = ShapeGflops(r.shape);
    if (srics::nn::GemmBackendAvailable(srics::nn::GemmBackend::kOneDnn)) {
      srics::nn::SetGemmBackend(srics::nn::GemmBackend::kOneDnn);
      r.onednn = ShapeGflops(r.shape);
    }
  }
  srics::nn::SetGemmBackend(active);
  return out;
}

}  // namespace

int main() {
  Eigen::setNbThreads(1);
  std::vector<Case> cases;
  for (int batch : {2048, 256}) {
    for (int entities : {4, 7}) {
      cases.push_back(RunCase(batch, entities, batch >= 2048 ? 11 : 31));
    }
  }
  const double act4 = ActMicros(4), act7 = ActMicros(7);

  std::printf(
      "nn benchmark: SAC attention networks (embed 80, 5 heads, policy [128,128], "
      "Q [128,128,128]), forward+backward, 1 thread, medians\n");
  std::printf("%6s %9s %11s %8s %14s %8s\n", "batch", "entities", "policy ms", "Q ms", "GEMM floor ms", "ratio");
  double total2048 = 0, floor2048 = 0;
  std::string json = "{\"bench\":\"nn\"";
  char buf[256];
  for (const Case& c : cases) {
    const double ratio = (c.policy_ms + c.q_ms) / c.floor_ms;
    std::printf("%6d %9d %11.2f %8.2f %14.2f %7.2fx\n", c.batch, c.entities, c.policy_ms, c.q_ms, c.floor_ms, ratio);
    if (c.batch == 2048) {
      total2048 += c.policy_ms + c.q_ms;
      floor2048 += c.floor_ms;
    }
    std::snprintf(buf, sizeof(buf), ",\"policy_ms_b%d_n%d\":%.3f,\"q_ms_b%d_n%d\":%.3f,\"floor_ms_b%d_n%d\":%.3f",
                  c.batch, c.entities, c.policy_ms, c.batch, c.entities, c.q_ms, c.batch, c.entities, c.floor_ms);
    json += buf;
  }
  const double ratio = total2048 / floor2048;
  std::printf("batch 2048 total: %.2f ms vs floor %.2f ms -> %.2fx (target <= 2x)\n", total2048, floor2048, ratio);
  std::printf(
      "single-observation action: %.1f us (4 entities), %.1f us (7 entities); "
      "target < 75 us (5%% of a 1.5 ms env step)\n",
      act4, act7);
  std::snprintf(buf, sizeof(buf), ",\"act_us_n4\":%.2f,\"act_us_n7\":%.2f,\"ratio\":%.3f}", act4, act7, ratio);
  json += buf;
  // products of batch 256 with 4 entities (the CPU profile's SAC batch)
  const std::vector<ShapeRate> rates = ShapeRates(cases[2].shapes);
  std::printf(
      "\nproducts of policy + Q at batch 256, 4 entities, GFLOP/s per distinct shape "
      "(matrix products now on %s)\n%22s %8s %8s %8s\n",
      srics::nn::GemmBackendDescription().c_str(), "m x k x n (ta tb)", "Eigen", "oneDNN", "ratio");
  double eigen_ms = 0, onednn_ms = 0;
  for (const ShapeRate& r : rates) {
    const GemmShape& g = r.shape;
    std::printf("%5ld x%5ld x%5ld (%d %d) %8.1f %8.1f %8.2f\n", static_cast<long>(g.m), static_cast<long>(g.k),
                static_cast<long>(g.n), g.transpose_a, g.transpose_b, r.eigen, r.onednn, r.onednn / r.eigen);
    const double flop = 2.0 * g.m * g.k * g.n;
    eigen_ms += flop / (r.eigen * 1e6);
    onednn_ms += r.onednn > 0 ? flop / (r.onednn * 1e6) : 0;
  }
  const double onednn_over_eigen = onednn_ms > 0 ? eigen_ms / onednn_ms : 0;
  std::printf("all distinct shapes once: oneDNN %.2fx Eigen's speed\n", onednn_over_eigen);
  json.pop_back();
  std::snprintf(buf, sizeof(buf), ",\"onednn_over_eigen_products_b256\":%.3f}", onednn_over_eigen);
  json += buf;
  std::printf("%s\n", json.c_str());
  return 0;
}
