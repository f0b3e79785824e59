// Development tool: learns the graph of a toy world and prints progress (not a test).
//   toy_learn PRESET SEED MAX_UPDATES [EPISODES]   PRESET: small | rearrange3 | relational4
#include <atomic>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tests/graph_service/toy_world.h"

using namespace srics;

int main(int argc, char** argv) {
  const std::string preset = argc > 1 ? argv[1] : "small";
  const uint64_t seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1;
  graph::testing::ToyWorldConfig world;
  if (preset == "small") { world.num_pucks = 2; world.static_pucks = {2}; }
  if (preset == "rearrange3") world.num_pucks = 3;
  if (preset == "relational4") { world.num_pucks = 4; world.static_pucks = {1}; world.ropes = {{2, 3}}; }
  config::GraphConfig cfg;
  cfg.max_updates = argc > 3 ? std::atoi(argv[3]) : 3000;
  cfg.episodes = argc > 4 ? std::atoi(argv[4]) : 1000;
  cfg.eval_every_updates = argc > 5 ? std::atoi(argv[5]) : 250;
  cfg.min_updates = cfg.max_updates;
  if (const char* v = std::getenv("WARMUP")) cfg.warmup_updates = std::atoi(v);
  if (const char* v = std::getenv("KL_RAMP")) cfg.kl_ramp_updates = std::atoi(v);
  if (const char* v = std::getenv("LR")) cfg.learning_rate = std::atof(v);
  if (const char* v = std::getenv("KL")) cfg.kl_weight = std::atof(v);
  graph::testing::ToySource source(world, cfg.episodes, seed * 100000);
  graph::testing::RecordingSink sink;
  graph::ServiceOptions options;
  options.seed = seed;
  options.state_dir = "/tmp/toy_learn_" + preset + "_" + std::to_string(seed);
  std::filesystem::remove_all(options.state_dir);
  graph::GraphService service(cfg, options, &source, &sink, [](const graph::Progress& p) {
    if (p.phase != graph::Progress::Phase::kTraining) return;
    std::printf("%7.1fs upd %6lld train %.3g held %.3g (zero %.3g)  %s\n   ", p.elapsed_seconds,
                static_cast<long long>(p.updates), p.train_loss, p.held_out_loss,
                p.held_out_zero_loss, p.graph.c_str());
    const int n = static_cast<int>(std::sqrt(p.mean_weights.size()) + 0.5);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) std::printf(" %.3f", p.mean_weights[i * n + j]);
      std::printf(" |");
    }
    std::printf("\n    entity mse/zero:");
    for (int i = 0; i < n; ++i) std::printf(" %.2g/%.2g", p.entity_loss[i], p.entity_zero_loss[i]);
    std::printf("\n");
    std::fflush(stdout);
  });
  std::atomic<bool> stop{false};
  return service.Run(stop);
}
