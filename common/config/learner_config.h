#pragma once
// The learner process: replay, relabeling, update schedule, rate limiting, checkpoints.

#include <cstdint>

namespace srics::config {

struct RelabelConfig {
  double original = 0.1;  // keep the episode's goal
  double future = 0.4;    // a future state of the same entity in the same episode
  double sampled = 0.5;   // a goal from the goal distribution
};

// Precision of the SAC update's matrix products (not a paper setting). bf16: operands rounded
// to bfloat16, fp32 sums, on CPUs with AVX-512 BF16 or AMX (elsewhere fp32, with a warning);
// weights, gradients and optimizer state stay fp32 either way.
enum class ProductPrecision { kFp32, kBf16 };

struct LearnerConfig {
  uint64_t replay_capacity = 250000;  // transitions; whole episodes leave oldest first
  uint64_t warmup_steps = 10000;      // random-action transitions before the first update
  double updates_per_step = 1.0;      // target update-to-data ratio
  double rate_error_buffer = 500;     // updates the learner may run ahead of (or behind) the ratio
  int publish_every_updates = 100;    // PolicyWeights period
  int checkpoint_every_updates = 5000;
  // checkpoints kept: the newest (checkpoint.srics) and keep_checkpoints - 1 older ones
  // (checkpoint.srics.1 the next older, ...), the fall-back when the newest is corrupt
  int keep_checkpoints = 3;
  // an update that meets a non-finite value is skipped (no network changes); this many in a
  // row mean the learner no longer learns (a diverged network or temperature), and the run
  // ends with an error naming the stage instead of training on unchanged. 0: never
  int max_skipped_updates_in_a_row = 2000;
  // whether the random exploration episodes collected for the interaction graph (graph
  // methods, before the graph and first weights exist) also enter the RL replay; they always
  // reach the graph service. true: the behaviour before this setting existed
  bool exploration_into_replay = true;
  // threads that share each SAC update (batch shards, gradients added in a fixed order: the
  // same math as one thread up to float summation order, deterministic for a given count).
  // Not a paper setting. 1: the behaviour before this setting existed, and the right choice
  // when the learner shares its cores with actors, the graph service or parallel runs; 2 on a
  // 2-core machine when the learner has both cores (docs/results.md, throughput)
  int threads = 1;
  ProductPrecision precision = ProductPrecision::kFp32;
  RelabelConfig relabel;
};

}  // namespace srics::config
