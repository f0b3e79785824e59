#include "deploy/monitor/monitor.h"

#include <spdlog/spdlog.h>

#include "common/transport/wire.h"

namespace srics::monitor {

namespace tr = srics::transport;

struct Monitor::Readers {
  tr::Reader<rl::NodeStatus> nodes;
  tr::Reader<rl::LearnerReport> learner;
  tr::Reader<rl::EvalReport> evals;
  tr::Reader<rl::GraphUpdate> graph;
  std::optional<tr::Reader<rl::WeightsUpdate>> weights;

  Readers(const tr::Participant& participant, const tr::ReaderOptions& options, bool with_weights)
      : nodes(participant, options),
        learner(participant, options),
        evals(participant, options),
        graph(participant, options) {
    if (with_weights) weights.emplace(participant, options);
  }
};

Monitor::Monitor(tr::Participant& participant, MonitorOptions options)
    : participant_(participant), options_(std::move(options)) {
  tr::ReaderOptions reader_options;
  reader_options.all_runs = options_.all_runs;
  readers_ = std::make_unique<Readers>(participant_, reader_options, options_.weights);
  if (!options_.csv_dir.empty()) csv_.emplace(options_.csv_dir);
  state_.lost_after = LostAfter(participant_.config());
  state_.max_nodes = static_cast<size_t>(participant_.config().monitor_max_nodes);
  state_.max_runs = static_cast<size_t>(participant_.config().monitor_max_runs);
  state_.own_run_id = PrintableText(participant_.config().run_id);
}

Monitor::~Monitor() = default;

size_t Monitor::Poll(std::chrono::milliseconds timeout) {
  constexpr size_t kMaxPerTopic = 10000;  // bounded work per poll even under a flood
  constexpr std::chrono::milliseconds kNoWait(0);
  size_t taken = 0;
  const double wall = WallTimeNow();

  rl::NodeStatus status;
  std::string run_id;
  std::chrono::milliseconds wait = timeout;
  for (size_t i = 0; i < kMaxPerTopic && readers_->nodes.Take(&status, wait, &run_id) == tr::TakeStatus::kSample; ++i) {
    wait = kNoWait;
    if (options_.accept_node && !options_.accept_node(status)) {
      participant_.CountRejection("status.foreign");
      continue;
    }
    Apply(&state_, run_id, status, Clock::now());
    if (csv_ && options_.csv_node_statuses) csv_->Append(run_id, status, wall);
    ++taken;
  }
  rl::LearnerReport stats;
  for (size_t i = 0; i < kMaxPerTopic && readers_->learner.Take(&stats, kNoWait, &run_id) == tr::TakeStatus::kSample;
       ++i) {
    if (options_.budget_env_steps) {
      const std::string problem = rl::ImplausibleProgress(stats.progress(), *options_.budget_env_steps);
      if (!problem.empty()) {
        Refuse("stats.implausible", "learner stats refused: " + problem);
        continue;
      }
    }
    Apply(&state_, run_id, stats, Clock::now());
    if (csv_) csv_->Append(run_id, stats, wall);
    ++taken;
  }
  rl::EvalReport result;
  for (size_t i = 0; i < kMaxPerTopic && readers_->evals.Take(&result, kNoWait, &run_id) == tr::TakeStatus::kSample;
       ++i) {
    if (result.policy_version == 0 && options_.passive_baseline) {
      if (!passive_played_) {
        passive_played_ = true;
        passive_baseline_ = options_.passive_baseline();
      }
      if (passive_baseline_) {
        if (const std::string problem = PassiveMismatch(result, *passive_baseline_); !problem.empty()) {
          ++RunOf(&state_, PrintableText(run_id), Clock::now()).passive_refused;
          Refuse("eval.passive", "passive evaluation (policy v0) from actor " + std::to_string(result.actor_id) +
                                     " refused, not this run's: " + problem);
          continue;
        }
      }
    }
    Apply(&state_, run_id, result, Clock::now());
    if (csv_) csv_->Append(run_id, result, wall);
    if (options_.on_eval) options_.on_eval(result);
    ++taken;
  }
  rl::GraphUpdate graph;
  for (size_t i = 0; i < kMaxPerTopic && readers_->graph.Take(&graph, kNoWait, &run_id) == tr::TakeStatus::kSample;
       ++i) {
    if (options_.num_entities > 0 && graph.graph.num_entities != options_.num_entities) {
      Refuse("graph.entities", "graph v" + std::to_string(graph.version) +
                                   " refused: " + std::to_string(graph.graph.num_entities) +
                                   " entities, this run has " + std::to_string(options_.num_entities));
      continue;
    }
    Apply(&state_, run_id, graph, Clock::now());
    ++taken;
  }
  if (readers_->weights) {
    rl::WeightsUpdate weights;
    for (size_t i = 0;
         i < kMaxPerTopic && readers_->weights->Take(&weights, kNoWait, &run_id) == tr::TakeStatus::kSample; ++i) {
      Apply(&state_, run_id, weights, Clock::now());
      if (options_.on_weights) options_.on_weights(weights);
      ++taken;
    }
    // the parameters are not needed here: give the megabytes back
    weights.parameters = std::vector<float>();
  }

  state_.dropped_samples = participant_.total_rejected();
  state_.status_writers_alive = readers_->nodes.alive_writers();
  state_.liveliness_known = true;
  const Clock::time_point now = Clock::now();
  for (const NodeKey& key : NewlyGone(state_, now, &known_gone_)) {
    const NodeEntry& node = state_.nodes.at(key);
    const NodeHealth health = known_gone_.at(key);
    std::string line =
        key.role + " " + std::to_string(key.node_id) + " (" + node.status.host + ", pid " +
        std::to_string(node.status.pid) + ", run " + key.run_id + ") " + NodeHealthName(health) + ": no status for " +
        std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(now - node.last_seen).count()) + " ms";
    if (health == NodeHealth::kLost)
      spdlog::warn("{}", line);
    else
      spdlog::info("{}", line);
    node_events_.push_back(std::move(line));
    if (csv_) csv_->Append(key.run_id, node.status, wall, health == NodeHealth::kLost ? "lost" : "exited");
  }
  return taken;
}

void Monitor::Refuse(const char* counter, const std::string& why) {
  participant_.CountRejection(counter);
  uint64_t suppressed = 0;
  if (refusals_log_.Allow(&suppressed)) spdlog::warn("{} ({} warnings suppressed)", why, suppressed);
}

std::vector<std::string> Monitor::TakeNodeEvents() {
  std::vector<std::string> events;
  events.swap(node_events_);
  return events;
}

}  // namespace srics::monitor
