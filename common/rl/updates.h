#pragma once
// What actors and the learner receive from the rest of the system, as plain data: the
// transport adapters of the process mains fill these from DDS samples.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/rl/evaluation.h"
#include "common/rl/graph.h"

namespace srics::rl {

// Sanity bound on policy parameters received or published: trained weights stay within a few
// units; a finite but huge parameter overflows the activations and gives NaN actions, which
// the environment refuses (the bound is the contract's, like kMaxAbsPosition in episode.h).
inline constexpr float kMaxAbsParameter = 1000.0f;

// Empty when every parameter is finite and within +-kMaxAbsParameter, else the first offender.
std::string ParameterProblem(const std::vector<float>& parameters);

// Policy parameters (topic PolicyWeights), as the learner publishes them and readers take them.
struct WeightsUpdate {
  uint64_t version = 0;
  uint64_t update_count = 0;
  std::string architecture;
  std::vector<float> parameters;
  bool operator==(const WeightsUpdate&) const = default;
};

// A published interaction graph (topic InteractionGraph): what the graph service sends and
// every process receives.
struct GraphUpdate {
  uint64_t version = 0;
  InteractionGraph graph;
  SubgoalStructure structure;        // derived from `graph`, never trusted from the wire
  std::vector<double> mean_weights;  // N x N, [i * N + j]
  double threshold = 0;
  double held_out_loss = 0;
  uint64_t training_updates = 0;
  uint32_t episodes_used = 0;
  bool operator==(const GraphUpdate&) const = default;
};

// The learner's progress as actors see it (rate limiting, evaluation schedule, run end).
struct LearnerProgress {
  uint64_t updates = 0;
  uint64_t transitions_inserted = 0;
  uint64_t policy_version = 0;
  uint64_t training_env_steps = 0;  // counted against the budget
  uint64_t budget_env_steps = 0;
  uint64_t replay_size = 0;  // transitions held (small after a learner restart)
  // updates the learner's own rate limit owes the data it counts: actors hold back while it is
  // above learner.rate_error_buffer (0 while the learner cannot update: warm-up, no graph)
  double update_backlog = 0;
  bool budget_done() const { return budget_env_steps > 0 && training_env_steps >= budget_env_steps; }
};

// Empty when `progress` can come from this run's learner, whose budget is `budget_env_steps`
// (run.total_env_steps); else why not. Checks what the actors act on: the budget itself,
// training steps within it and within the transitions inserted, the replay within the inserts.
// A sample of the right run id that passes is still not proven to be the learner's (only DDS
// Security's access control can say who wrote it: common/transport/README.md).
std::string ImplausibleProgress(const LearnerProgress& progress, uint64_t budget_env_steps);

// The learner's statistics (topic LearnerStats), as published and as actors and monitors read
// them.
struct LearnerReport {
  uint64_t updates = 0;
  uint64_t transitions_inserted = 0;
  uint64_t training_env_steps = 0;  // counted against the budget
  uint64_t budget_env_steps = 0;
  uint64_t replay_size = 0;
  double update_backlog = 0;  // see LearnerProgress
  uint64_t episodes_accepted = 0;
  uint64_t episodes_rejected = 0;
  uint64_t policy_version = 0;
  double q_loss = 0;
  double policy_loss = 0;
  double alpha = 0;
  double entropy = 0;
  double mean_reward = 0;
  double updates_per_second = 0;
  double inserts_per_second = 0;  // transitions
  LearnerProgress progress() const {
    return {updates,          transitions_inserted, policy_version, training_env_steps,
            budget_env_steps, replay_size,          update_backlog};
  }
  bool operator==(const LearnerReport&) const = default;
};

// One evaluation (topic EvalResult), as published and as monitors read it. The wire has no
// count of episodes with a defined selectivity: received, every episode counts.
struct EvalReport {
  uint32_t actor_id = 0;
  uint64_t policy_version = 0;  // 0 = the passive policy (the baseline)
  uint64_t graph_version = 0;
  uint64_t env_steps = 0;  // system env steps when it ran
  EvaluationSummary summary;
  bool operator==(const EvalReport&) const = default;
};

// A process's phase (NodeStatus.state). The values are the wire's (idl/srics.idl NodeState,
// tied by a static_assert in the transport library): a received value out of range stays
// representable, and validation (not a cast) refuses it.
enum class NodePhase : int32_t {
  kStarting = 0,
  kWaiting = 1,
  kExploring = 2,
  kTraining = 3,
  kEvaluating = 4,
  kStopping = 5,
  kFailed = 6,
};

// Lowercase names ("starting", "training", ...) for logs and files; "invalid" out of range.
const char* NodePhaseName(NodePhase phase);

// A process's health, as its loop reports it.

struct NodeReport {
  NodePhase phase = NodePhase::kStarting;
  uint64_t policy_version = 0;
  uint64_t graph_version = 0;
  uint64_t steps = 0;    // env steps (actors) or updates (learner)
  uint64_t dropped = 0;  // samples rejected by this node's own checks
  std::string detail;
  // what the node's own checks rejected, per counter ("weights.architecture": 2); the
  // transport adds its own and shows them in NodeStatus.detail
  std::map<std::string, uint64_t> rejections;
  bool operator==(const NodeReport&) const = default;
};

// A process's health as published (topic NodeStatus): who and where it is, and its report.
// The rejections are not on the wire (the publisher folds them into the detail): received,
// report.rejections is empty.
struct NodeStatus {
  std::string role;  // actor, learner, graph, monitor, launcher
  uint32_t node_id = 0;
  std::string host;
  int32_t pid = 0;
  uint64_t uptime_ms = 0;
  NodeReport report;
  bool operator==(const NodeStatus&) const = default;
};

}  // namespace srics::rl
