// srics-actor CONFIG --id K [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]
// One actor process: MuJoCo environments, the latest policy, whole episodes over DDS.

#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "actor/actor_loop.h"
#include "common/process/role_startup.h"
#include "common/transport/graph_feed.h"
#include "common/transport/rl_convert.h"
#include "common/transport/status_publisher.h"
#include "common/transport/transport.h"

namespace srics {
namespace {

namespace tr = transport;

// The actor's DDS side: newest weights/graph/learner stats, episodes and evaluations out.
class DdsActorLink : public actor::ActorLink {
 public:
  DdsActorLink(const tr::Participant& participant, uint32_t actor_id)
      : weights_(participant),
        graphs_(participant),
        stats_(participant),
        episodes_(participant),
        evals_(participant),
        status_(participant, "actor", actor_id) {
    // the learner and the graph service: episodes written before they listen are lost
    // (volatile), so give discovery a moment; go on without them after that
    episodes_.WaitForReaders(2, std::chrono::seconds(3));
  }

  std::optional<rl::WeightsUpdate> PollWeights() override {
    tr::PolicyWeights message;
    std::optional<rl::WeightsUpdate> newest;
    while (weights_.Take(&message, std::chrono::milliseconds(0)) == tr::TakeStatus::kSample) {
      if (message.version <= weights_version_) continue;
      weights_version_ = message.version;
      newest = rl::WeightsUpdate{message.version, message.update_count, message.architecture,
                                 std::move(message.parameters)};
    }
    return newest;
  }

  std::optional<rl::GraphUpdate> PollGraph() override { return graphs_.PollNewest(); }

  std::optional<rl::LearnerProgress> PollLearner(std::chrono::milliseconds wait) override {
    tr::LearnerStats message;
    for (auto timeout = wait; stats_.Take(&message, timeout) == tr::TakeStatus::kSample;
         timeout = std::chrono::milliseconds(0)) {
      progress_ = rl::LearnerProgress{message.updates, message.transitions_inserted, message.policy_version,
                                      message.training_env_steps, message.budget_env_steps, message.replay_size};
    }
    return progress_;
  }

  bool PublishEpisode(const rl::Episode& episode) override {
    return episodes_.Write(tr::ToMessage(episode)) == tr::WriteResult::kSent;
  }

  void PublishEval(const rl::EvalReport& report) override {
    tr::EvalResult m;
    m.actor_id = report.actor_id;
    m.policy_version = report.policy_version;
    m.graph_version = report.graph_version;
    m.env_steps = report.env_steps;
    m.episodes = static_cast<uint32_t>(report.summary.episodes);
    m.avg_distance = static_cast<float>(report.summary.avg_distance);
    m.avg_object_distance = static_cast<float>(report.summary.avg_object_distance);
    m.success_rate = static_cast<float>(report.summary.success_rate);
    m.entity_distance.assign(report.summary.entity_distance.begin(), report.summary.entity_distance.end());
    m.subgoal_success.assign(report.summary.subgoal_success.begin(), report.summary.subgoal_success.end());
    m.selectivity = static_cast<float>(report.summary.selectivity_episodes ? report.summary.selectivity : 0.0);
    if (evals_.Write(m) != tr::WriteResult::kSent) spdlog::warn("evaluation not sent: shutting down");
  }

  void PublishStatus(const rl::NodeReport& report) override {
    rl::NodeReport r = report;
    r.dropped += graphs_.rejected();
    status_.Publish(r);
  }

 private:
  tr::Reader<tr::PolicyWeights> weights_;
  tr::GraphFeed graphs_;
  tr::Reader<tr::LearnerStats> stats_;
  tr::Writer<tr::Episode> episodes_;
  tr::Writer<tr::EvalResult> evals_;
  tr::StatusPublisher status_;
  uint64_t weights_version_ = 0;
  std::optional<rl::LearnerProgress> progress_;
};

// How many times this actor has started in this run folder (a small state file), so that a
// restarted actor's episode ids keep increasing: generation << 32 | episode count.
uint64_t NextGeneration(const std::string& path) {
  uint64_t generation = 0;
  std::ifstream(path) >> generation;
  std::ofstream(path) << generation + 1 << "\n";
  return generation;
}

}  // namespace
}  // namespace srics

int main(int argc, char** argv) {
  using namespace srics;
  transport::Shutdown::InstallSignalHandlers();
  process::Role role;
  if (const int code = process::StartRole(
          argc, argv, "srics-actor",
          "srics-actor CONFIG --id K [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]", "actor",
          /*needs_id=*/true, &role))
    return code;
  const config::CommandLine& cl = role.command_line;
  const config::Config& config = role.config;
  const uint32_t id = static_cast<uint32_t>(*cl.id);
  const std::string& name = role.name;
  uint64_t first_id = 0;
  if (!cl.run_dir.empty()) {
    std::filesystem::create_directories(cl.run_dir + "/state");
    first_id = NextGeneration(cl.run_dir + "/state/" + name + ".generation") << 32;
  }
  try {
    transport::Participant participant(config.transport);
    DdsActorLink link(participant, id);
    actor::ActorLoop loop(config, id, &link, first_id);
    spdlog::info("{} started: {} ({}), domain {}, run id '{}', first episode id {}", name,
                 config::MethodName(config.run.method), config.source_file, config.transport.domain_id,
                 config.transport.run_id, first_id);
    const int code = loop.Run(transport::Shutdown::Process().flag());
    const auto& c = loop.counters();
    spdlog::info("{} stopped: {} episodes, {} env steps, {} evaluations, {} unstable, {} weights refused, {} waits",
                 name, c.episodes, c.env_steps, c.evaluations, c.unstable_episodes, c.weights_rejected, c.waits);
    return code;
  } catch (const std::exception& e) {
    spdlog::critical("{} failed: {}", name, e.what());
    return 1;
  }
}
