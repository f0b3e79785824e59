// ./tests/bench.sh sac-update: milliseconds per full SAC update (batch sampling and goal
// relabeling, twin critics, policy, temperature, target update) with the paper's networks on
// Rearrange 3 (4 entities), at batch 2048 and 256, one thread; and in the same run the GEMM
// floor: the same matrix products as bare Eigen products.

#include <cstdio>
#include <memory>

#include "actor/env/rearrange_env.h"
#include "actor/rollout.h"
#include "common/config/config.h"
#include "learner/learner.h"
#include "tests/bench/bench_util.h"

namespace {

using namespace srics;

struct Result {
  int batch;
  double update_ms, floor_ms;
  size_t gemms;
};

Result Measure(int batch, const std::vector<rl::Episode>& episodes, int repeats) {
  config::Config c = config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-3.yaml",
                                        {"agent.sac.batch_size=" + std::to_string(batch),
                                         "learner.warmup_steps=0"});
  learner::Learner learner(learner::LearnerOptionsFor(c));
  learner.SetGraph(rl::ComputeSubgoalStructure(rl::InteractionGraph::Star(4)));
  for (const auto& e : episodes) learner.Ingest(e);
  std::vector<nn::GemmShape> shapes;
  learner.agent().set_gemm_log(&shapes);
  learner.Update();
  learner.agent().set_gemm_log(nullptr);
  bench::GemmFloor floor(shapes);
  Result r{batch, 0, 0, shapes.size()};
  r.update_ms = bench::MedianMs(repeats, [&] { learner.Update(); });
  r.floor_ms = bench::MedianMs(repeats, [&] { floor.Run(); });
  return r;
}

}  // namespace

int main() {
  config::Config c = config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-3.yaml");
  auto env = env::MakeRearrangeEnv(c.env);
  nn::Rng rng(1);
  std::vector<rl::Episode> episodes;
  for (int i = 0; i < 200; ++i)
    if (auto e = actor::RunExploreEpisode(*env, 50, 1000 + i, rng)) episodes.push_back(std::move(*e));

  std::printf("SAC update, paper networks (attention 80 = 5 x 16, policy [128,128], Q [128,128,128]),\n"
              "Rearrange 3 (4 entities), one thread, median of repeats\n\n");
  std::printf("%-8s %14s %14s %8s %8s\n", "batch", "update ms", "GEMM floor ms", "ratio", "gemms");
  const Result big = Measure(2048, episodes, 11);
  const Result small = Measure(256, episodes, 41);
  for (const Result& r : {big, small})
    std::printf("%-8d %14.2f %14.2f %8.2f %8zu\n", r.batch, r.update_ms, r.floor_ms, r.update_ms / r.floor_ms, r.gemms);
  std::printf("\nupdates per second at batch 256: %.0f; at 2048: %.1f\n", 1000.0 / small.update_ms,
              1000.0 / big.update_ms);
  std::printf("{\"bench\":\"sac-update\",\"ms_batch2048\":%.3f,\"ms_batch256\":%.3f,\"floor_ms_batch2048\":%.3f,"
              "\"floor_ms_batch256\":%.3f,\"ratio\":%.3f}\n",
              big.update_ms, small.update_ms, big.floor_ms, small.floor_ms, big.update_ms / big.floor_ms);
  return 0;
}
