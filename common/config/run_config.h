#pragma once
// Settings of one experiment as a whole: name, seed, method, budget, output and logging.

#include <cstdint>
#include <string>

namespace srics::config {

// The methods of the paper and its ablations; all run on the same machinery.
enum class Method {
  kSrics,                      // selectivity reward + independently controllable subgoals + depth order
  kSricsNoSelectivity,         // ablation: ICS subgoals and depth order, distance reward only
  kSricsNoSelectivityNoOrder,  // ablation: also random subgoal order at evaluation
  kSmorl,                      // per-object distance reward, all objects as subgoals, random order
  kSacHer,                     // flat state, full goal
  kHac,                        // hierarchical actor-critic baseline
};

const char* MethodName(Method method);

struct RunConfig {
  std::string name = "srics";  // run folder name prefix
  uint64_t seed = 1;           // base seed; actor k uses seed + 1000 * (k + 1)
  Method method = Method::kSrics;
  uint64_t total_env_steps = 600000;  // training budget (paper: 600k for 3 pucks)
  double max_wall_minutes = 0;        // 0 = no wall-clock limit
  std::string output_dir = "runs";    // run folders are created below this
  std::string log_level = "info";     // trace, debug, info, warn, error
  bool log_to_file = true;            // also write <run folder>/logs/<role>.log
  // `srics run --in-process`: 1 steps every loop on one thread; 2 steps the learner on a second
  // thread beside the actors, each round's publications delivered at its end (a fixed schedule,
  // as deterministic as 1 but not the same trajectory). Recorded only when given.
  int in_process_threads = 1;
};

}  // namespace srics::config
