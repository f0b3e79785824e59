#include "common/transport/status_publisher.h"

#include <unistd.h>

namespace srics::transport {

NodeState ToNodeState(rl::NodePhase phase) {
  switch (phase) {
    case rl::NodePhase::kStarting: return NodeState::kStarting;
    case rl::NodePhase::kWaiting: return NodeState::kWaiting;
    case rl::NodePhase::kExploring: return NodeState::kExploring;
    case rl::NodePhase::kTraining: return NodeState::kTraining;
    case rl::NodePhase::kEvaluating: return NodeState::kEvaluating;
    case rl::NodePhase::kStopping: return NodeState::kStopping;
    case rl::NodePhase::kFailed: return NodeState::kFailed;
  }
  return NodeState::kFailed;
}

StatusPublisher::StatusPublisher(const Participant& participant, std::string role, uint32_t node_id)
    : participant_(&participant), writer_(participant), start_(std::chrono::steady_clock::now()) {
  char host[kHostMaxLength] = {};
  gethostname(host, sizeof host - 1);
  status_.role = std::move(role);
  status_.node_id = node_id;
  status_.host = host;
  status_.pid = static_cast<int32_t>(getpid());
}

void StatusPublisher::Publish(const rl::NodeReport& report) {
  status_.state = ToNodeState(report.phase);
  status_.policy_version = report.policy_version;
  status_.graph_version = report.graph_version;
  status_.env_steps = report.steps;
  status_.dropped_samples = report.dropped + participant_->total_rejected();
  status_.uptime_ms = static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                                std::chrono::steady_clock::now() - start_)
                                                .count());
  status_.detail = report.detail.substr(0, kDetailMaxLength - 1);
  (void)writer_.TryWrite(status_);  // a status lost to back-pressure is replaced by the next
}

}  // namespace srics::transport
