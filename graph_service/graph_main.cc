// srics-graph CONFIG [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]
// The graph service process: collects explore episodes over DDS, trains the recurrent GNN,
// publishes the interaction graph (versioned, transient-local), saves it to DIR/graph.json
// and re-publishes the saved graph on restart without retraining.

#include <spdlog/spdlog.h>

#include "common/process/role_startup.h"
#include "common/rl/agent_shape.h"
#include "common/transport/dds_links.h"
#include "common/transport/transport.h"
#include "graph_service/service.h"

int main(int argc, char** argv) {
  using namespace srics;
  transport::Shutdown::InstallSignalHandlers();
  const process::RoleProgram program{
      "srics-graph", "graph", false,
      "the graph service (learns the interaction graph from explore episodes, publishes it)"};
  return process::RunRole(argc, argv, program, [](const process::Role& role) {
    const config::Config& config = role.config;
    transport::Participant participant(config.transport);
    const graph_service::ServiceOptions options =
        graph_service::ServiceOptionsFor(config, rl::RunShapeFor(config), role.command_line.run_dir);
    transport::DdsEpisodeSource source(participant, options.limits, static_cast<size_t>(config.graph.episodes),
                                       config.graph.refine_after_publish);
    transport::DdsGraphSink sink(participant);
    graph_service::GraphService service(config.graph, options, &source, &sink, nullptr);
    spdlog::info("graph service started: domain {}, run id '{}', {} explore episodes wanted",
                 config.transport.domain_id, config.transport.run_id, config.graph.episodes);
    // after the publication, steps keep the episode topic drained and the graph available
    // (transient-local lives in this process) until asked to stop
    const auto& stop = transport::Shutdown::Process().flag();
    int code = 0;
    try {
      while (!stop) {
        if (service.Step(options.poll_timeout) == graph_service::StepResult::kDone) {
          code = 1;  // the source closed before a graph was published
          break;
        }
      }
    } catch (const graph_service::GnnTrainingDivergedError& e) {
      // a restart would resume the same model from its training checkpoint: not restarted
      throw process::UnusableStateError(e.what());
    }
    service.Stop();
    spdlog::info("graph service stopped");
    return code;
  });
}
