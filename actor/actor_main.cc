// srics-actor CONFIG --id K [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]
// One actor process: MuJoCo environments, the latest policy, whole episodes over DDS.

#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>

#include "actor/actor_loop.h"
#include "common/process/role_startup.h"
#include "common/rl/agent_shape.h"
#include "common/transport/dds_links.h"
#include "common/transport/transport.h"

namespace srics {
namespace {

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
  return process::RunRole(argc, argv, {"srics-actor", "actor", /*needs_id=*/true}, [](const process::Role& role) {
    const config::CommandLine& cl = role.command_line;
    const config::Config& config = role.config;
    const uint32_t id = static_cast<uint32_t>(*cl.id);
    const std::string& name = role.name;
    uint64_t first_id = 0;
    if (!cl.run_dir.empty()) {
      std::filesystem::create_directories(cl.run_dir + "/state");
      first_id = NextGeneration(cl.run_dir + "/state/" + name + ".generation") << 32;
    }
    transport::Participant participant(config.transport);
    transport::DdsActorLink link(participant, id, rl::EpisodeLimitsFor(config.env));
    actor::ActorLoop loop(actor::ActorOptionsFor(config, id, first_id), &link);
    spdlog::info("{} started: {} ({}), domain {}, run id '{}', first episode id {}", name,
                 config::MethodName(config.run.method), config.source_file, config.transport.domain_id,
                 config.transport.run_id, first_id);
    const int code = loop.Run(transport::Shutdown::Process().flag());
    const auto& c = loop.counters();
    spdlog::info("{} stopped: {} episodes, {} env steps, {} evaluations, {} unstable, {} weights refused, {} waits",
                 name, c.episodes, c.env_steps, c.evaluations, c.unstable_episodes, c.weights_rejected, c.waits);
    return code;
  });
}
