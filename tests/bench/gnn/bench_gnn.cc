// ./tests/bench.sh gnn: milliseconds per GNN training update (batch 100 windows of 20 steps,
// 5 entities, paper sizes) on one thread, against the "GEMM floor": the same matrix products
// (shapes logged by the tape during one update) run as bare Eigen products. The last line is
// one JSON object with "ratio" = update time / GEMM floor.
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "graph_service/trainer.h"
#include "tests/bench/bench_util.h"
#include "tests/graph_service/toy_world.h"

namespace {

using srics::nn::GemmShape;
using srics::nn::Tensor;
using Clock = std::chrono::steady_clock;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

template <typename F>
double BestOf(int repeats, F&& f) {
  double best = 1e30;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    f();
    best = std::min(best, Ms(Clock::now() - start));
  }
  return best;
}

}  // namespace

int main() {
  Eigen::setNbThreads(1);
  // relational-4 shaped toy data: 5 entities
  srics::graph_service::testing::ToyWorld world(
      {.num_pucks = 4, .static_pucks = {1}, .ropes = {{2, 3}}});
  srics::graph_service::GraphDataset data = srics::graph_service::GraphDataset::ShapedLike(world.RandomEpisode(0));
  for (int e = 0; e < 60; ++e) data.Add(world.RandomEpisode(e + 1));
  data.Split(0.1, 1);
  srics::config::GraphConfig config;  // paper sizes: batch 100, window 20, hidden 20, MLP 100
  config.warmup_updates = 0;          // time the gated phase (the longer one)
  srics::graph_service::GnnTrainer trainer(config, data, 1);
  for (int i = 0; i < 3; ++i) trainer.Update();  // buffers sized
  std::vector<GemmShape> shapes;
  trainer.set_gemm_log(&shapes);
  trainer.Update();
  trainer.set_gemm_log(nullptr);
  const int repeats = 10;
  const double update_ms = BestOf(repeats, [&] { trainer.Update(); });
  srics::bench::GemmFloor floor(shapes);
  const double flops = floor.Flops();
  floor.Run();
  const double floor_ms = BestOf(repeats, [&] { floor.Run(); });
  const double eval_ms = BestOf(1, [&] { trainer.Evaluate(); });
  std::printf("GNN training update, one thread (batch %d windows x %d steps, %d entities, "
              "hidden %d, MLP %d)\n", config.batch_windows, config.window, data.num_entities(),
              config.hidden_dim, config.mlp_hidden);
  std::printf("  %-34s %10s\n", "measure", "value");
  std::printf("  %-34s %10.2f\n", "update ms (best of 10)", update_ms);
  std::printf("  %-34s %10.2f\n", "GEMM floor ms (same products)", floor_ms);
  std::printf("  %-34s %10zu\n", "matrix products per update", shapes.size());
  std::printf("  %-34s %10.3f\n", "GFLOP per update (products)", flops * 1e-9);
  std::printf("  %-34s %10.2f\n", "GEMM floor GFLOP/s", flops * 1e-6 / floor_ms);
  std::printf("  %-34s %10.2f\n", "update / floor", update_ms / floor_ms);
  std::printf("  %-34s %10.1f\n", "evaluation ms (60 episodes x 50)", eval_ms);
  std::printf("  %-34s %10.0f\n", "updates per 15 min (no evals)", 900000.0 / update_ms);
  std::printf("{\"bench\":\"gnn\",\"update_ms\":%.3f,\"gemm_floor_ms\":%.3f,\"gemms\":%zu,"
              "\"gflop\":%.4f,\"entities\":%d,\"batch\":%d,\"window\":%d,\"ratio\":%.3f}\n",
              update_ms, floor_ms, shapes.size(), flops * 1e-9, data.num_entities(),
              config.batch_windows, config.window, update_ms / floor_ms);
  return 0;
}
