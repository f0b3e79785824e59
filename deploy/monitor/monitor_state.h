#pragma once
// What a monitor knows about the runs on a domain, built only from received samples. Plain
// data and pure functions: the display and the CSV files are computed from it, and tests
// build it by hand without DDS.
//
//   MonitorState state;
//   state.lost_after = LostAfter(config.transport);
//   Apply(&state, node_status, Clock::now());
//   std::string text = Render(state, Clock::now(), {});   // display.h

#include <chrono>
#include <compare>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/config/transport_config.h"
#include "common/rl/evaluation.h"
#include "common/rl/updates.h"
#include "common/transport/wire.h"

namespace srics::monitor {

using Clock = std::chrono::steady_clock;

// A node is one process of a run: NodeStatus is keyed by (run_id, role, node_id).
struct NodeKey {
  std::string run_id;
  std::string role;
  uint32_t node_id = 0;
  auto operator<=>(const NodeKey&) const = default;
};

// How a node looks from here.
enum class NodeHealth {
  kAlive,   // a status arrived within lost_after
  kQuiet,   // no status for lost_after, but DDS liveliness says every status writer is alive:
            // a busy process (or a status thread starved of CPU), not a dead one
  kExited,  // its last status said "stopping", then it went quiet: a clean exit
  kLost,    // went quiet without saying goodbye: crashed, killed or cut off
};
const char* NodeHealthName(NodeHealth health);

struct NodeEntry {
  rl::NodeStatus status;  // the latest one
  Clock::time_point first_seen;
  Clock::time_point last_seen;
  uint64_t statuses = 0;  // samples received
};

// The latest policy weights, without their parameters (megabytes the monitor has no use for).
struct WeightsInfo {
  uint64_t version = 0;
  uint64_t update_count = 0;
  std::string architecture;
  size_t num_parameters = 0;
  Clock::time_point received;
};

// One LearnerStats as a point of the learner's history (the dashboard's loss and rate charts).
struct LearnerPoint {
  uint64_t updates = 0;
  uint64_t env_steps = 0;  // training env steps (transitions inserted where the contract lacks them)
  float q_loss = 0, policy_loss = 0, alpha = 0, entropy = 0, mean_reward = 0;
  float updates_per_second = 0, inserts_per_second = 0;
};

// A bounded, evenly thinned history: every `stride`-th point is kept; when more than
// `max_points` are held, every other one is dropped and the stride doubles. The newest point
// is always `latest` (so a chart ends where the learner is).
struct LearnerHistory {
  std::vector<LearnerPoint> points;
  std::optional<LearnerPoint> latest;
  uint64_t stride = 1;
  uint64_t seen = 0;
  size_t max_points = 600;
};
void Add(LearnerHistory* history, const LearnerPoint& point);

// Everything about one run id.
struct RunView {
  std::optional<rl::LearnerReport> learner;
  Clock::time_point learner_received;
  std::optional<rl::EvalReport> passive;  // the first EvalResult with policy_version 0
  // policy-version-0 results refused as not this run's passive baseline (PassiveMismatch;
  // counted by Monitor, which knows the baseline), shown beside the passive line
  uint64_t passive_refused = 0;
  std::vector<rl::EvalReport> evals;     // policy_version > 0, oldest first (bounded)
  std::optional<rl::GraphUpdate> graph;  // its structure as received (masks and depths)
  Clock::time_point graph_received;
  std::optional<WeightsInfo> weights;
  // (arrival, training env steps) of recent LearnerStats, for the rate and the ETA: the last
  // kRateWindow of them, cleared when the count goes back (a learner restarted afresh)
  std::deque<std::pair<Clock::time_point, uint64_t>> step_history;
  // every LearnerStats, thinned (cleared with step_history when the learner starts afresh)
  LearnerHistory learner_history;
  Clock::time_point last_sample;  // the newest sample of any topic (which run goes first)
  uint64_t samples = 0;           // samples of any topic folded in
};

// How far back the env-step rate looks.
inline constexpr std::chrono::seconds kRateWindow{60};

struct MonitorState {
  std::map<NodeKey, NodeEntry> nodes;
  std::map<std::string, RunView> runs;
  // A node that sent nothing for this long is no longer alive (see LostAfter).
  std::chrono::milliseconds lost_after{5000};
  size_t max_evals_kept = 1000;  // per run, oldest dropped first
  // Keys from the wire are bounded (transport.monitor_max_nodes / monitor_max_runs): past the
  // limit the entry heard from least goes (one sample before many; then the longest silent),
  // never `own_run_id`'s run; evictions are counted and shown.
  size_t max_nodes = 1024;
  size_t max_runs = 64;
  std::string own_run_id;  // the run this monitor belongs to ("" = none)
  uint64_t evicted_nodes = 0;
  uint64_t evicted_runs = 0;
  uint64_t dropped_samples = 0;       // malformed samples the monitor's readers rejected
  uint32_t status_writers_alive = 0;  // NodeStatus writers alive by their liveliness lease
  bool liveliness_known = false;      // status_writers_alive is filled in (by Monitor)
};

// When a silent node counts as gone: its liveliness lease plus two status periods (a live
// node sends a status every period, so this is never reached while it is alive).
std::chrono::milliseconds LostAfter(const config::TransportConfig& transport);

// A peer's string as it may be shown on a terminal or written to a CSV: every byte outside
// printable ASCII (control characters, escape sequences, C1 codes in UTF-8) becomes '?'.
// Anything on the domain can publish: a run id or a detail must not drive the terminal.
std::string PrintableText(std::string_view text);

// The run's view, created when new (evicting another past max_runs) and marked as heard now.
RunView& RunOf(MonitorState* state, const std::string& printable_run_id, Clock::time_point now);

// Folding samples into the state. `now` is the arrival time. Every string of a sample (run
// id, role, host, detail, architecture) is kept as PrintableText; `run_id` is the sample's
// (its envelope's).
void Apply(MonitorState* state, const std::string& run_id, const rl::NodeStatus& status, Clock::time_point now);
void Apply(MonitorState* state, const std::string& run_id, const rl::LearnerReport& stats, Clock::time_point now);
void Apply(MonitorState* state, const std::string& run_id, const rl::EvalReport& result, Clock::time_point now);
void Apply(MonitorState* state, const std::string& run_id, const rl::GraphUpdate& graph, Clock::time_point now);
// Keeps the version and size only.
void Apply(MonitorState* state, const std::string& run_id, const rl::WeightsUpdate& weights, Clock::time_point now);

// How far a received passive evaluation may lie from the baseline a recorder played itself
// (actor::PlayPassiveBaseline): float rounding of the wire's fields (1e-7 relative) with a wide
// margin, yet a thousand times finer than the distances it guards (0.1-0.2 m).
inline constexpr double kPassiveTolerance = 1e-4;

// Why `result` (policy version 0) cannot be the run's passive evaluation whose figures are
// `expected` (played by the recorder on the run's evaluation goals): another episode count, or
// an average distance, average object distance, success rate or per-entity distance further
// than kPassiveTolerance (relative, at least 1e-4 m) from the expected one, or not finite.
// Empty when it agrees. Selectivity, subgoal success and graph version are not compared (they
// depend on the subgoals the actor used, not on the passive policy).
std::string PassiveMismatch(const rl::EvalReport& result, const rl::EvaluationSummary& expected);

// kAlive within lost_after of its last status; then kExited if that status said "stopping",
// kQuiet if liveliness is known and at least as many status writers are alive as there are
// nodes that did not say goodbye, else kLost.
NodeHealth HealthOf(const MonitorState& state, const NodeEntry& node, Clock::time_point now);

// Nodes whose health changed to kLost or kExited since `*known_gone`, which is updated (for
// logging and for the "lost" rows of nodes.csv). Nodes that come back are removed from it.
std::vector<NodeKey> NewlyGone(const MonitorState& state, Clock::time_point now,
                               std::map<NodeKey, NodeHealth>* known_gone);

// Environment steps of a run as the system reports them: the larger of the learner's count
// against the budget (LearnerStats.training_env_steps where the contract has it, else
// transitions_inserted) and the latest evaluation's env_steps (0 when neither arrived).
uint64_t EnvSteps(const RunView& run);

// The budget the learner announces (LearnerStats.budget_env_steps), 0 when unknown.
uint64_t BudgetEnvSteps(const RunView& run);
// Training env steps per second over the last kRateWindow of learner stats; empty until
// stats span at least 5 s.
std::optional<double> EnvStepRate(const RunView& run);

// The newest evaluation of a trained policy, or null.
const rl::EvalReport* LatestEval(const RunView& run);

// Edges of a graph (adjacency entries that are 1, the diagonal excluded).
size_t EdgeCount(const rl::GraphUpdate& graph);

}  // namespace srics::monitor
