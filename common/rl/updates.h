#pragma once
// What actors and the learner receive from the rest of the system, as plain data: the
// transport adapters of the process mains fill these from DDS samples.

#include <cstdint>
#include <string>
#include <vector>

#include "common/rl/evaluation.h"
#include "common/rl/graph.h"

namespace srics::rl {

struct WeightsUpdate {
  uint64_t version = 0;
  uint64_t update_count = 0;
  std::string architecture;
  std::vector<float> parameters;
};

// A published interaction graph: what the graph service sends and every process receives.
struct GraphUpdate {
  uint64_t version = 0;
  InteractionGraph graph;
  SubgoalStructure structure;       // derived from `graph`, never trusted from the wire
  std::vector<double> mean_weights; // N x N, [i * N + j]
  double threshold = 0;
  double held_out_loss = 0;
  uint64_t training_updates = 0;
  uint32_t episodes_used = 0;
};

// The learner's progress as actors see it (rate limiting, evaluation schedule, run end).
struct LearnerProgress {
  uint64_t updates = 0;
  uint64_t transitions_inserted = 0;
  uint64_t policy_version = 0;
  uint64_t training_env_steps = 0;  // counted against the budget
  uint64_t budget_env_steps = 0;
  uint64_t replay_size = 0;         // transitions held (small after a learner restart)
  bool budget_done() const { return budget_env_steps > 0 && training_env_steps >= budget_env_steps; }
};

// The learner's statistics, as published (LearnerStats) and as actors read them.
struct LearnerReport {
  uint64_t updates = 0;
  uint64_t transitions_inserted = 0;
  uint64_t training_env_steps = 0;  // counted against the budget
  uint64_t budget_env_steps = 0;
  uint64_t replay_size = 0;
  uint64_t episodes_accepted = 0;
  uint64_t episodes_rejected = 0;
  uint64_t policy_version = 0;
  double q_loss = 0;
  double policy_loss = 0;
  double alpha = 0;
  double entropy = 0;
  double mean_reward = 0;
  double updates_per_second = 0;
  double inserts_per_second = 0;   // transitions
  LearnerProgress progress() const {
    return {updates, transitions_inserted, policy_version, training_env_steps, budget_env_steps, replay_size};
  }
};

// One evaluation, as published.
struct EvalReport {
  uint32_t actor_id = 0;
  uint64_t policy_version = 0;  // 0 = the passive policy (the baseline)
  uint64_t graph_version = 0;
  uint64_t env_steps = 0;       // system env steps when it ran
  EvaluationSummary summary;
};

// A process's health for NodeStatus.
enum class NodePhase { kStarting, kWaiting, kExploring, kTraining, kEvaluating, kStopping, kFailed };

struct NodeReport {
  NodePhase phase = NodePhase::kStarting;
  uint64_t policy_version = 0;
  uint64_t graph_version = 0;
  uint64_t steps = 0;     // env steps (actors) or updates (learner)
  uint64_t dropped = 0;   // samples rejected by this node's own checks
  std::string detail;
};

}  // namespace srics::rl
