// Development tool: learns the graph of a toy world and prints progress (not a test).
//   toy_learn PRESET SEED MAX_UPDATES [EPISODES]   PRESET: small | rearrange3 | relational4
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "tests/graph_service/progress_printer.h"
#include "tests/graph_service/toy_world.h"

using namespace srics;

int main(int argc, char** argv) {
  const std::string preset = argc > 1 ? argv[1] : "small";
  const uint64_t seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1;
  graph_service::testing::ToyWorldConfig world;
  if (preset == "small") {
    world.num_pucks = 2;
    world.static_pucks = {2};
  }
  if (preset == "rearrange3") world.num_pucks = 3;
  if (preset == "relational4") {
    world.num_pucks = 4;
    world.static_pucks = {1};
    world.ropes = {{2, 3}};
  }
  config::GraphConfig cfg;
  cfg.max_updates = argc > 3 ? std::atoi(argv[3]) : 3000;
  cfg.episodes = argc > 4 ? std::atoi(argv[4]) : 1000;
  cfg.eval_every_updates = argc > 5 ? std::atoi(argv[5]) : 250;
  cfg.min_updates = cfg.max_updates;
  if (const char* v = std::getenv("WARMUP")) cfg.warmup_updates = std::atoi(v);
  if (const char* v = std::getenv("KL_RAMP")) cfg.kl_ramp_updates = std::atoi(v);
  if (const char* v = std::getenv("LR")) cfg.learning_rate = std::atof(v);
  if (const char* v = std::getenv("KL")) cfg.kl_weight = std::atof(v);
  graph_service::testing::ToySource source(world, cfg.episodes, seed * 100000);
  graph_service::testing::RecordingSink sink;
  graph_service::ServiceOptions options;
  options.seed = seed;
  options.state_dir = "/tmp/toy_learn_" + preset + "_" + std::to_string(seed);
  std::filesystem::remove_all(options.state_dir);
  graph_service::GraphService service(cfg, options, &source, &sink, graph_service::testing::PrintTrainingProgress);
  std::atomic<bool> stop{false};
  return service.Run(stop);
}
