// srics-learner CONFIG [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]
// The learner process: replay, relabeling and SAC on the episodes of every actor; publishes
// policy weights and stats over DDS; checkpoints to DIR/checkpoint.srics and resumes from it.

#include <spdlog/spdlog.h>

#include <iostream>

#include "common/logging/logging.h"
#include "common/process/role_startup.h"
#include "common/nn/serialize.h"
#include "common/rl/agent_shape.h"
#include "common/transport/dds_links.h"
#include "common/transport/transport.h"
#include "learner/learner_loop.h"

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
    transport::DdsLearnerLink link(participant, rl::EpisodeLimitsFor(config.env));
    learner::LearnerLoop loop(
        learner::LearnerLoopOptionsFor(config, cl.run_dir.empty() ? "" : cl.run_dir + "/checkpoint.srics"), &link);
    spdlog::info("learner started: {} ({}), domain {}, run id '{}', budget {} env steps",
                 config::MethodName(config.run.method), config.source_file, config.transport.domain_id,
                 config.transport.run_id, config.run.total_env_steps);
    return loop.Run(transport::Shutdown::Process().flag());
  } catch (const std::exception& e) {
    spdlog::critical("learner failed: {}", e.what());
    return 1;
  }
}
