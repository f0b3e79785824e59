// srics-graph CONFIG [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]
// The graph service process: collects explore episodes over DDS, trains the recurrent GNN,
// publishes the interaction graph (versioned, transient-local), saves it to DIR/graph.json
// and re-publishes the saved graph on restart without retraining.

#include <spdlog/spdlog.h>

#include <atomic>
#include <condition_variable>
#include <iostream>
#include <mutex>
#include <thread>

#include "common/process/role_startup.h"
#include "common/rl/agent_shape.h"
#include "common/transport/dds_links.h"
#include "common/transport/transport.h"
#include "graph_service/service.h"

namespace srics {
namespace {

rl::NodePhase PhaseOf(graph::Progress::Phase phase) {
  switch (phase) {
    case graph::Progress::Phase::kLoading: return rl::NodePhase::kStarting;
    case graph::Progress::Phase::kCollecting: return rl::NodePhase::kWaiting;
    case graph::Progress::Phase::kTraining: return rl::NodePhase::kTraining;
    case graph::Progress::Phase::kPublished: return rl::NodePhase::kWaiting;
    case graph::Progress::Phase::kStopped: return rl::NodePhase::kStopping;
  }
  return rl::NodePhase::kFailed;
}

}  // namespace
}  // namespace srics

int main(int argc, char** argv) {
  using namespace srics;
  transport::Shutdown::InstallSignalHandlers();
  process::Role role;
  if (const int code = process::StartRole(
          argc, argv, "srics-graph",
          "srics-graph CONFIG [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]", "graph",
          /*needs_id=*/false, &role))
    return code;
  const config::CommandLine& cl = role.command_line;
  const config::Config& config = role.config;
  try {
    transport::Participant participant(config.transport);
    transport::DdsEpisodeSource source(participant, rl::EpisodeLimitsFor(config.env),
                                       static_cast<size_t>(config.graph.episodes));
    transport::DdsGraphSink sink(participant);
    // NodeStatus from a heartbeat thread: GNN training blocks the service's own thread for
    // seconds at a time, and monitors must not take a busy service for a dead one
    transport::StatusPublisher status(participant, "graph", 0);
    std::mutex progress_mutex;
    graph::Progress last;
    auto report = [&]() {
      graph::Progress p;
      {
        std::lock_guard lock(progress_mutex);
        p = last;
      }
      rl::NodeReport r;
      r.phase = PhaseOf(p.phase);
      r.graph_version = p.published_version;
      r.steps = static_cast<uint64_t>(p.updates);
      r.dropped = static_cast<uint64_t>(p.dropped) + source.rejected();
      r.detail = std::string(graph::PhaseName(p.phase)) + ": " + std::to_string(p.episodes) + "/" +
                 std::to_string(p.target_episodes) + " episodes, " + std::to_string(p.updates) + " updates" +
                 (p.held_out_loss >= 0 ? ", held-out " + std::to_string(p.held_out_loss) : "") +
                 (p.graph.empty() ? "" : ", " + p.graph);
      status.Publish(r);
    };
    const auto& stop = transport::Shutdown::Process().flag();
    // a jthread: asked to stop and joined on every way out of this scope, exceptions included
    std::jthread heartbeat([&](std::stop_token token) {
      const auto period = std::chrono::duration<double>(config.transport.status_period_s);
      while (!token.stop_requested() && !stop) {
        report();
        std::this_thread::sleep_for(std::chrono::duration_cast<std::chrono::milliseconds>(period));
      }
    });
    graph::ServiceOptions options;
    options.state_dir = cl.run_dir;
    options.seed = config.run.seed;
    graph::GraphService service(config.graph, options, &source, &sink, [&](const graph::Progress& p) {
      std::lock_guard lock(progress_mutex);
      last = p;
    });
    spdlog::info("graph service started: domain {}, run id '{}', {} explore episodes wanted",
                 config.transport.domain_id, config.transport.run_id, config.graph.episodes);
    const int code = service.Run(stop);
    // keep the graph available (transient-local lives in this process) until asked to stop;
    // the source's thread keeps draining the episode topic meanwhile
    while (!stop && code == 0) {
      std::vector<rl::Episode> unused;
      source.Poll(std::chrono::milliseconds(500), &unused);
    }
    heartbeat.request_stop();
    heartbeat.join();
    {
      std::lock_guard lock(progress_mutex);
      last = service.progress();
      last.phase = graph::Progress::Phase::kStopped;
    }
    report();
    spdlog::info("graph service stopped");
    return 0;
  } catch (const std::exception& e) {
    spdlog::critical("graph service failed: {}", e.what());
    return 1;
  }
}
