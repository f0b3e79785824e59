// srics-learner CONFIG [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]
// The learner process: replay, relabeling and SAC on the episodes of every actor; publishes
// policy weights and stats over DDS; checkpoints to DIR/checkpoint.srics and resumes from it.

#include <spdlog/spdlog.h>

#include "common/logging/logging.h"
#include "common/nn/gemm.h"
#include "common/nn/serialize.h"
#include "common/process/role_startup.h"
#include "common/rl/agent_shape.h"
#include "common/transport/dds_links.h"
#include "common/transport/transport.h"
#include "learner/learner_loop.h"

int main(int argc, char** argv) {
  using namespace srics;
  transport::Shutdown::InstallSignalHandlers();
  const process::RoleProgram program{"srics-learner", "learner", false,
                                     "the learner (replay, relabeling, SAC; publishes weights and stats, checkpoints)"};
  return process::RunRole(argc, argv, program, [](const process::Role& role) {
    const config::Config& config = role.config;
    const std::string& run_dir = role.command_line.run_dir;
    transport::Participant participant(config.transport);
    const rl::RunShape shape = rl::RunShapeFor(config);
    transport::DdsLearnerLink link(participant, shape.limits);
    learner::LearnerLoop loop(
        learner::LearnerLoopOptionsFor(config, shape, run_dir.empty() ? "" : run_dir + "/checkpoint.srics"), &link);
    spdlog::info(
        "learner started: {} ({}), domain {}, run id '{}', budget {} env steps, "
        "matrix products on {}",
        config::MethodName(config.run.method), config.source_file, config.transport.domain_id, config.transport.run_id,
        config.run.total_env_steps, nn::GemmBackendDescription());
    try {
      loop.Start();  // the checkpoint: a run whose checkpoints are unusable is not restarted over them
    } catch (const nn::CheckpointError& e) {
      throw process::UnusableStateError(e.what());
    }
    try {
      return loop.Run(transport::Shutdown::Process().flag());
    } catch (const learner::LearningDivergedError& e) {
      // a restart would resume the same networks from their checkpoint: not restarted
      throw process::UnusableStateError(e.what());
    }
  });
}
