#include "learner/learner_loop.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <thread>

namespace srics::learner {

using Clock = std::chrono::steady_clock;

LearnerLoop::LearnerLoop(const config::Config& config, LearnerLink* link, LearnerLoopOptions options)
    : config_(config), link_(link), options_(std::move(options)), learner_(config) {}

void LearnerLoop::Publish() {
  rl::WeightsUpdate w;
  w.parameters = learner_.TakePolicyWeights();
  w.version = learner_.counters().policy_version;
  w.update_count = learner_.counters().updates;
  w.architecture = learner_.agent().PolicySignature();
  link_->PublishWeights(w);
}

void LearnerLoop::Report(bool force) {
  const double dt = std::chrono::duration<double>(Clock::now() - last_report_).count();
  if (!force && dt < config_.transport.status_period_s) return;
  LearnerReport r;
  r.counters = learner_.counters();
  r.replay_size = learner_.replay().transitions();
  r.episodes_rejected = learner_.episodes_rejected();
  r.last_update = last_update_;
  if (dt > 0) {
    r.updates_per_second = (r.counters.updates - updates_at_report_) / dt;
    r.inserts_per_second = (r.counters.transitions_inserted - inserted_at_report_) / dt;
  }
  link_->PublishStats(r);
  rl::NodeReport status;
  status.phase = learner_.CanUpdate() || r.counters.updates > 0 ? rl::NodePhase::kTraining : rl::NodePhase::kWaiting;
  status.policy_version = r.counters.policy_version;
  status.graph_version = graph_version_;
  status.steps = r.counters.updates;
  status.dropped = r.episodes_rejected;
  status.detail = "replay " + std::to_string(r.replay_size) + ", inserted " +
                  std::to_string(r.counters.transitions_inserted) +
                  (learner_.has_graph() || !rl::UsesGraph(config_.run.method) ? "" : ", waiting for the graph");
  link_->PublishStatus(status);
  last_report_ = Clock::now();
  updates_at_report_ = r.counters.updates;
  inserted_at_report_ = r.counters.transitions_inserted;
}

int LearnerLoop::Run(const std::atomic<bool>& stop) {
  if (!options_.checkpoint_path.empty() && std::filesystem::exists(options_.checkpoint_path)) {
    learner_.LoadCheckpoint(options_.checkpoint_path);
    // weights published after that checkpoint carried higher versions than it records: skip
    // past every version that can have been used, so versions keep increasing for actors
    learner_.SkipPolicyVersions(config_.learner.checkpoint_every_updates / config_.learner.publish_every_updates + 2);
    spdlog::info("resumed from {}: {} updates, {} transitions inserted, policy v{}", options_.checkpoint_path,
                 learner_.counters().updates, learner_.counters().transitions_inserted,
                 learner_.counters().policy_version);
  }
  // actors start training once weights exist: publish the initial ones at once
  Publish();
  last_report_ = Clock::now();
  Report(true);
  uint64_t checkpointed_at = learner_.counters().updates;
  std::vector<rl::Episode> episodes;
  bool done = false;
  while (!stop && !done) {
    episodes.clear();
    const bool work = learner_.CanUpdate();
    link_->TakeEpisodes(&episodes, 64, work ? std::chrono::milliseconds(0) : std::chrono::milliseconds(50));
    for (auto& e : episodes) {
      const std::string problem = learner_.Ingest(std::move(e));
      if (!problem.empty()) spdlog::warn("episode rejected: {}", problem);
    }
    if (auto g = link_->PollGraph()) {
      const int entities = 1 + static_cast<int>(config::EffectiveObjects(config_.env).size());
      if (g->graph.num_entities != entities) {
        spdlog::warn("graph v{} has {} entities, this run's environment {}: ignored", g->version,
                     g->graph.num_entities, entities);
      } else {
        learner_.SetGraph(g->structure);
        graph_version_ = g->version;
        spdlog::info("graph v{}: {}", g->version, rl::DescribeGraph(g->graph));
      }
    }
    for (int i = 0; i < options_.max_updates_per_poll && learner_.CanUpdate() && !stop; ++i)
      last_update_ = learner_.Update();
    if (learner_.counters().updates > 0 && learner_.PublishDue()) Publish();
    if (!options_.checkpoint_path.empty() &&
        learner_.counters().updates >= checkpointed_at + config_.learner.checkpoint_every_updates) {
      learner_.SaveCheckpoint(options_.checkpoint_path);
      checkpointed_at = learner_.counters().updates;
    }
    Report(false);
    done = learner_.BudgetReached() && !learner_.CanUpdate();
  }
  // final weights first, then the stats that tell actors the budget is done
  Publish();
  if (!options_.checkpoint_path.empty()) learner_.SaveCheckpoint(options_.checkpoint_path);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  Report(true);
  spdlog::info("learner {}: {} updates, {} transitions, policy v{}", done ? "done" : "stopped",
               learner_.counters().updates, learner_.counters().transitions_inserted,
               learner_.counters().policy_version);
  return 0;
}

}  // namespace srics::learner
