#pragma once
// A monitor attached to a domain: readers of NodeStatus, LearnerStats, EvalResult,
// InteractionGraph and (optionally) PolicyWeights fold every sample into a MonitorState and,
// when asked, into CSV files. Used by srics-monitor and by the launcher's progress display.
//
//   transport::Participant participant(config.transport);
//   Monitor monitor(participant, {.csv_dir = "runs/x"});
//   while (!participant.shutdown_requested()) {
//     monitor.Poll(std::chrono::milliseconds(250));
//     std::cout << Render(monitor.state(), Clock::now(), {});
//   }
//
// Threading: one thread calls Poll and reads state().

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "common/logging/logging.h"
#include "common/transport/transport.h"
#include "deploy/monitor/csv_sink.h"
#include "deploy/monitor/monitor_state.h"

namespace srics::monitor {

struct MonitorOptions {
  bool all_runs = false;          // accept samples of every run id (else only the participant's)
  bool weights = true;            // subscribe to PolicyWeights (5 MB per publication over the wire)
  std::string csv_dir;            // append eval.csv, learner.csv, nodes.csv here ("" = no CSV)
  bool csv_node_statuses = true;  // every NodeStatus as a row (else only lost/exited events)
  // What the run's own samples look like, when the monitor knows its run (the launcher):
  // LearnerStats that rl::ImplausibleProgress refuses for this budget ("stats.implausible")
  // and graphs of another entity count ("graph.entities") are dropped and counted, never
  // shown or written to learner.csv. Unset / 0: anything valid on the wire is taken.
  std::optional<uint64_t> budget_env_steps;
  int num_entities = 0;
  // The run's passive baseline, played by the recorder itself (the launcher:
  // actor::PlayPassiveBaseline), called once, when the first policy-version-0 EvalResult
  // arrives. Set, a v0 result that disagrees with it (PassiveMismatch) is refused
  // ("eval.passive"), counted in RunView::passive_refused and never shown, written to eval.csv
  // or passed to on_eval: a stranger cannot set the run's baseline. Returning empty (it could
  // not be played) accepts v0 results as they come. Unset: anything valid on the wire is taken.
  std::function<std::optional<rl::EvaluationSummary>()> passive_baseline;
  // Set: a NodeStatus it returns false for is refused ("status.foreign"): neither in the state,
  // the display nor nodes.csv (the launcher: a second launcher of its run id, which leaves).
  std::function<bool(const rl::NodeStatus&)> accept_node;
  // Called with every evaluation and every weights sample taken (may be empty): for what a
  // program keeps besides the state (the launcher: the best evaluation's weights).
  std::function<void(const rl::EvalReport&)> on_eval;
  std::function<void(const rl::WeightsUpdate&)> on_weights;
};

class Monitor {
 public:
  // Creates the readers. Throws transport::DdsError, std::runtime_error (CSV files).
  Monitor(transport::Participant& participant, MonitorOptions options);
  ~Monitor();
  Monitor(const Monitor&) = delete;
  Monitor& operator=(const Monitor&) = delete;

  // Waits up to `timeout` for a node status, then takes everything available on every topic,
  // folds it into the state (and the CSV files) and checks nodes that went quiet. Returns the
  // number of samples taken.
  size_t Poll(std::chrono::milliseconds timeout);

  const MonitorState& state() const { return state_; }
  MonitorState& mutable_state() { return state_; }

  // Nodes that went quiet in the last Poll, as "actor 1 (host) LOST" lines, and forgets them.
  std::vector<std::string> TakeNodeEvents();

 private:
  struct Readers;
  // counts a refused sample under `counter` and logs `why` at a limited rate
  void Refuse(const char* counter, const std::string& why);
  transport::Participant& participant_;
  MonitorOptions options_;
  std::unique_ptr<Readers> readers_;
  std::optional<CsvSink> csv_;
  MonitorState state_;
  std::map<NodeKey, NodeHealth> known_gone_;
  std::vector<std::string> node_events_;
  logging::RateLimiter refusals_log_{std::chrono::seconds(5)};
  // options_.passive_baseline's answer, once asked
  bool passive_played_ = false;
  std::optional<rl::EvaluationSummary> passive_baseline_;
};

}  // namespace srics::monitor
