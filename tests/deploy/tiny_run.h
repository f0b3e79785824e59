#pragma once
// The settings of the deploy tests' runs of a few seconds on Rearrange 1: a graph from 20
// episodes and 40 GNN updates, a short warm-up, batch 32, two episodes per evaluation. Each
// test adds its budget, actors and evaluation interval.

#include <string>
#include <vector>

namespace srics::testing {

inline std::vector<std::string> TinyRunSettings(const std::vector<std::string>& own) {
  std::vector<std::string> settings = own;
  for (const char* set : {"learner.warmup_steps=200", "agent.sac.batch_size=32", "learner.publish_every_updates=20",
                          "actors.eval_episodes=2", "graph.episodes=20", "graph.batch_windows=10",
                          "graph.warmup_updates=10", "graph.kl_ramp_updates=10", "graph.min_updates=40",
                          "graph.max_updates=40", "graph.eval_every_updates=20", "run.max_wall_minutes=0"})
    settings.push_back(set);
  return settings;
}

}  // namespace srics::testing
