// srics-learner CONFIG [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]
// The learner process: replay, relabeling and SAC on the episodes of every actor; publishes
// policy weights and stats over DDS; checkpoints to DIR/checkpoint.srics and resumes from it.

#include <spdlog/spdlog.h>

#include <iostream>

#include "common/logging/logging.h"
#include "common/process/role_startup.h"
#include "common/nn/serialize.h"
#include "common/transport/graph_feed.h"
#include "common/transport/rl_convert.h"
#include "common/transport/status_publisher.h"
#include "common/transport/transport.h"
#include "learner/learner_loop.h"

namespace srics {
namespace {

namespace tr = transport;

class DdsLearnerLink : public learner::LearnerLink {
 public:
  DdsLearnerLink(const tr::Participant& participant, bool velocities, uint64_t budget)
      : velocities_(velocities),
        budget_(budget),
        episodes_(participant),
        graphs_(participant),
        weights_(participant),
        stats_(participant),
        status_(participant, "learner", 0),
        limiter_(std::chrono::seconds(participant.config().rejected_log_interval_s)) {}

  size_t TakeEpisodes(std::vector<rl::Episode>* out, size_t max, std::chrono::milliseconds wait) override {
    messages_.clear();
    episodes_.TakeMany(&messages_, max, wait);
    size_t added = 0;
    for (const auto& m : messages_) {
      try {
        out->push_back(tr::FromMessage(m, velocities_));
        ++added;
      } catch (const std::invalid_argument& e) {
        ++rejected_;
        uint64_t suppressed = 0;
        if (limiter_.Allow(&suppressed))
          spdlog::warn("episode from actor {} refused: {} ({} more suppressed)", m.actor_id, e.what(), suppressed);
      }
    }
    return added;
  }

  std::optional<rl::GraphUpdate> PollGraph() override { return graphs_.PollNewest(); }

  void PublishWeights(const rl::WeightsUpdate& w) override {
    tr::PolicyWeights m;
    m.version = w.version;
    m.update_count = w.update_count;
    m.architecture = w.architecture;
    m.parameters = w.parameters;
    // on the way out (shutdown requested) one plain attempt still goes out if there is room
    if (weights_.Write(m) != tr::WriteResult::kSent && weights_.TryWrite(m) != tr::WriteResult::kSent)
      spdlog::info("weights v{} not sent: shutting down", w.version);
  }

  void PublishStats(const learner::LearnerReport& r) override {
    tr::LearnerStats m;
    m.updates = r.counters.updates;
    m.transitions_inserted = r.counters.transitions_inserted;
    m.training_env_steps = r.counters.training_env_steps;
    m.budget_env_steps = budget_;
    m.replay_size = r.replay_size;
    m.episodes_accepted = r.counters.episodes_accepted;
    m.episodes_rejected = r.episodes_rejected + rejected_;
    m.policy_version = r.counters.policy_version;
    m.q_loss = static_cast<float>(r.last_update.q_loss);
    m.policy_loss = static_cast<float>(r.last_update.policy_loss);
    m.alpha = static_cast<float>(r.last_update.alpha);
    m.entropy = static_cast<float>(r.last_update.entropy);
    m.updates_per_second = static_cast<float>(r.updates_per_second);
    m.inserts_per_second = static_cast<float>(r.inserts_per_second);
    m.mean_reward = static_cast<float>(r.last_update.mean_reward);
    (void)stats_.TryWrite(m);
  }

  void PublishStatus(const rl::NodeReport& report) override {
    rl::NodeReport r = report;
    r.dropped += rejected_ + graphs_.rejected();
    status_.Publish(r);
  }

 private:
  bool velocities_;
  uint64_t budget_;
  tr::Reader<tr::Episode> episodes_;
  tr::GraphFeed graphs_;
  tr::Writer<tr::PolicyWeights> weights_;
  tr::Writer<tr::LearnerStats> stats_;
  tr::StatusPublisher status_;
  logging::RateLimiter limiter_;
  std::vector<tr::Episode> messages_;
  uint64_t rejected_ = 0;
};

}  // namespace
}  // namespace srics

int main(int argc, char** argv) {
  using namespace srics;
  transport::Shutdown::InstallSignalHandlers();
  process::Role role;
  if (const int code = process::StartRole(
          argc, argv, "srics-learner",
          "srics-learner CONFIG [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]", "learner",
          /*needs_id=*/false, &role))
    return code;
  const config::CommandLine& cl = role.command_line;
  const config::Config& config = role.config;
  try {
    transport::Participant participant(config.transport);
    DdsLearnerLink link(participant, config.env.velocities, config.run.total_env_steps);
    learner::LearnerLoopOptions options;
    if (!cl.run_dir.empty()) options.checkpoint_path = cl.run_dir + "/checkpoint.srics";
    learner::LearnerLoop loop(config, &link, options);
    spdlog::info("learner started: {} ({}), domain {}, run id '{}', budget {} env steps",
                 config::MethodName(config.run.method), config.source_file, config.transport.domain_id,
                 config.transport.run_id, config.run.total_env_steps);
    return loop.Run(transport::Shutdown::Process().flag());
  } catch (const std::exception& e) {
    spdlog::critical("learner failed: {}", e.what());
    return 1;
  }
}
