#include "deploy/launcher/stall_watch.h"

#include <algorithm>
#include <cmath>

namespace srics::launcher {

StallWatch::StallWatch(std::chrono::milliseconds stall_after, std::string run_id, std::vector<WatchedNode> nodes)
    : stall_after_(stall_after),
      run_id_(std::move(run_id)),
      nodes_(std::move(nodes)),
      reported_pid_(nodes_.size(), 0) {}

std::vector<std::pair<size_t, std::string>> StallWatch::Check(const Supervisor& supervisor,
                                                              const monitor::MonitorState& state,
                                                              monitor::Clock::time_point now) {
  std::vector<std::pair<size_t, std::string>> hung;
  if (stall_after_.count() <= 0) return hung;
  for (size_t k = 0; k < nodes_.size(); ++k) {
    const WatchedNode& node = nodes_[k];
    const ChildStatus& child = supervisor.status(node.child);
    if (child.phase != ChildPhase::kRunning || child.pid == reported_pid_[k]) continue;
    // the supervisor's clock and the monitor's are both steady_clock
    monitor::Clock::time_point last = child.started_at;
    bool heard = false;
    const auto entry = state.nodes.find(monitor::NodeKey{run_id_, node.role, node.node_id});
    if (entry != state.nodes.end() && static_cast<int>(entry->second.status.pid) == child.pid) {
      last = std::max(last, entry->second.last_seen);
      heard = true;
    }
    if (now - last < stall_after_) continue;
    const double seconds = std::chrono::duration<double>(now - last).count();
    hung.emplace_back(node.child, std::string("hung: ") +
                                      (heard ? "no NodeStatus for " : "no NodeStatus since its start ") +
                                      std::to_string(static_cast<int>(std::lround(seconds))) +
                                      " s while its process runs (transport.stalled_node_restart_s)");
    reported_pid_[k] = child.pid;
  }
  return hung;
}

}  // namespace srics::launcher
