#pragma once
// Liveness of the role processes beyond "the process exists": a role whose NodeStatus stopped
// while its process still runs (a deadlock, an endless loop, a stopped process) is hung, and
// only a restart helps. The supervisor sees exits; this sees silence.
//
//   StallWatch watch(std::chrono::seconds(300), run_id, {{index, "actor", 2}, ...});
//   for (auto& [index, why] : watch.Check(supervisor, monitor.state(), now)) supervisor.Kill(index, why);

#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "deploy/launcher/supervisor.h"
#include "deploy/monitor/monitor_state.h"

namespace srics::launcher {

// Which node (NodeStatus role and id) a supervised child is.
struct WatchedNode {
  size_t child = 0;  // supervisor index
  std::string role;  // "learner", "graph", "actor"
  uint32_t node_id = 0;
};

class StallWatch {
 public:
  // stall_after <= 0: never reports.
  StallWatch(std::chrono::milliseconds stall_after, std::string run_id, std::vector<WatchedNode> nodes);

  // Children that run and have sent no NodeStatus from their current process (its pid) for
  // stall_after, counted from their last status or, without one, from their start; with why.
  // A child is reported once per incarnation.
  std::vector<std::pair<size_t, std::string>> Check(const Supervisor& supervisor, const monitor::MonitorState& state,
                                                    monitor::Clock::time_point now);

 private:
  std::chrono::milliseconds stall_after_;
  std::string run_id_;
  std::vector<WatchedNode> nodes_;
  std::vector<int> reported_pid_;  // per node: the pid last reported (no second report for it)
};

}  // namespace srics::launcher
