// srics-actor CONFIG --id K [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]
// One actor process: MuJoCo environments, the latest policy, whole episodes over DDS.

#include <spdlog/spdlog.h>

#include "actor/actor_loop.h"
#include "actor/recording/video_recorder.h"
#include "common/process/role_startup.h"
#include "common/rl/agent_shape.h"
#include "common/transport/dds_links.h"
#include "common/transport/transport.h"

int main(int argc, char** argv) {
  using namespace srics;
  transport::Shutdown::InstallSignalHandlers();
  const process::RoleProgram program{
      "srics-actor", "actor", /*needs_id=*/true,
      "one actor process (MuJoCo environments, the latest policy, whole episodes over DDS)"};
  return process::RunRole(argc, argv, program, [](const process::Role& role) {
    const process::CommandLine& cl = role.command_line;
    const config::Config& config = role.config;
    const uint32_t id = static_cast<uint32_t>(*cl.id);
    const std::string& name = role.name;
    // a restarted actor's episode ids keep increasing
    const uint64_t first_id = process::NextActorFirstEpisodeId(cl.run_dir, name);
    transport::Participant participant(config.transport);
    const rl::RunShape shape = rl::RunShapeFor(config);
    transport::DdsActorLink link(participant, id, shape.limits, config.run.total_env_steps);
    actor::ActorLoop loop(actor::ActorOptionsFor(config, shape, id, first_id), &link);
    loop.set_eval_recorder(actor::RecorderFor(config, loop.environment(), id, cl.run_dir));
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
