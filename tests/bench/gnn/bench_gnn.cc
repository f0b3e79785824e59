// ./tests/bench.sh gnn: milliseconds per GNN training update (batch 100 windows of 20 steps,
// 5 entities, paper sizes) on one thread, against the "GEMM floor": the same matrix products
// (shapes logged by the tape during one update) run as bare products through the same GEMM
// (common/nn/gemm.h), and the update with Eigen's GEMM instead of oneDNN's. Best of 10 by wall
// time and by the thread's CPU time (which holds on a machine shared with other work). The
// last line is one JSON object with "ratio" = update CPU time / GEMM floor CPU time.
#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <vector>

#include "common/nn/gemm.h"
#include "graph_service/trainer.h"
#include "tests/bench/bench_util.h"
#include "tests/graph_service/toy_world.h"

namespace {

using srics::nn::GemmShape;
using srics::nn::Tensor;
using Clock = std::chrono::steady_clock;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

double ThreadCpuMs() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * t.tv_sec + 1e-6 * t.tv_nsec;
}
struct Best {
  double wall = 1e30, cpu = 1e30;
};
template <typename F>
Best BestOf(int repeats, F&& f) {
  Best best;
  for (int r = 0; r < repeats; ++r) {
    const double cpu0 = ThreadCpuMs();
    const auto start = Clock::now();
    f();
    best.wall = std::min(best.wall, Ms(Clock::now() - start));
    best.cpu = std::min(best.cpu, ThreadCpuMs() - cpu0);
  }
  return best;
}

}  // namespace

int main() {
  Eigen::setNbThreads(1);
  // relational-4 shaped toy data: 5 entities
  srics::graph_service::testing::ToyWorld world({.num_pucks = 4, .static_pucks = {1}, .ropes = {{2, 3}}});
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
  const Best update = BestOf(repeats, [&] { trainer.Update(); });
  const srics::nn::GemmBackend active = srics::nn::ActiveGemmBackend();
  srics::nn::SetGemmBackend(srics::nn::GemmBackend::kEigen);
  const Best update_eigen = BestOf(repeats, [&] { trainer.Update(); });
  srics::nn::SetGemmBackend(active);
  srics::bench::GemmFloor floor(shapes);
  const double flops = floor.Flops();
  floor.Run();
  const Best floor_best = BestOf(repeats, [&] { floor.Run(); });
  const Best eval = BestOf(1, [&] { trainer.Evaluate(); });
  std::printf(
      "GNN training update, one thread (batch %d windows x %d steps, %d entities, "
      "hidden %d, MLP %d), matrix products on %s\n",
      config.batch_windows, config.window, data.num_entities(), config.hidden_dim, config.mlp_hidden,
      srics::nn::GemmBackendDescription().c_str());
  std::printf("  %-40s %10s %10s\n", "measure (best of 10)", "wall", "CPU");
  std::printf("  %-40s %10.2f %10.2f\n", "update ms", update.wall, update.cpu);
  std::printf("  %-40s %10.2f %10.2f\n", "update ms with Eigen's GEMM", update_eigen.wall, update_eigen.cpu);
  std::printf("  %-40s %10.2f %10.2f\n", "GEMM floor ms (same products)", floor_best.wall, floor_best.cpu);
  std::printf("  %-40s %10.2f %10.2f\n", "update / floor", update.wall / floor_best.wall, update.cpu / floor_best.cpu);
  std::printf("  %-40s %10zu\n", "matrix products per update", shapes.size());
  std::printf("  %-40s %10.3f\n", "GFLOP per update (products)", flops * 1e-9);
  std::printf("  %-40s %10.2f %10.2f\n", "GEMM floor GFLOP/s", flops * 1e-6 / floor_best.wall,
              flops * 1e-6 / floor_best.cpu);
  std::printf("  %-40s %10.1f %10.1f\n", "evaluation ms (60 episodes x 50)", eval.wall, eval.cpu);
  std::printf("  %-40s %10.0f %10.0f\n", "updates per 15 min (no evals)", 900000.0 / update.wall,
              900000.0 / update.cpu);
  std::printf(
      "{\"bench\":\"gnn\",\"update_ms\":%.3f,\"update_cpu_ms\":%.3f,\"update_cpu_ms_eigen\":%.3f,"
      "\"gemm_floor_ms\":%.3f,\"gemm_floor_cpu_ms\":%.3f,\"gemms\":%zu,\"gflop\":%.4f,"
      "\"entities\":%d,\"batch\":%d,\"window\":%d,\"gemm_backend\":\"%s\",\"ratio_wall\":%.3f,"
      "\"ratio\":%.3f}\n",
      update.wall, update.cpu, update_eigen.cpu, floor_best.wall, floor_best.cpu, shapes.size(), flops * 1e-9,
      data.num_entities(), config.batch_windows, config.window, srics::nn::GemmBackendDescription().c_str(),
      update.wall / floor_best.wall, update.cpu / floor_best.cpu);
  return 0;
}
