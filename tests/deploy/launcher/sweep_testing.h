// What the sweep tests share: the tiny runs they sweep and the srics program as a child.
#ifndef SRICS_TESTS_DEPLOY_LAUNCHER_SWEEP_TESTING_H_
#define SRICS_TESTS_DEPLOY_LAUNCHER_SWEEP_TESTING_H_

#include <chrono>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "deploy/launcher/child_process.h"
#include "tests/common/files/test_files.h"

namespace srics::launcher::testing {

inline const std::string kConfig = std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml";

// Runs of a few seconds: a graph from 20 episodes and 40 GNN updates, 1500 training steps.
inline const std::vector<std::string> kTinyRun = {
    "run.total_env_steps=1500", "learner.warmup_steps=200", "agent.sac.batch_size=32",
    "learner.publish_every_updates=20", "learner.checkpoint_every_updates=100", "actors.count=1",
    "actors.eval_every_env_steps=500", "actors.eval_episodes=2", "graph.episodes=20", "graph.batch_windows=10",
    "graph.warmup_updates=10", "graph.kl_ramp_updates=10", "graph.min_updates=40", "graph.max_updates=40",
    "graph.eval_every_updates=20", "run.max_wall_minutes=0"};

// The exit code (minus the signal number when killed) and output of `srics ARGS...`.
inline std::pair<int, std::string> RunSrics(const std::filesystem::path& root, std::vector<std::string> args) {
  args.insert(args.begin(), SRICS_LAUNCHER);
  const std::string out = (root / "srics.out").string();
  std::filesystem::remove(out);
  ChildProcess child = ChildProcess::Spawn(args, {.output_file = out});
  const auto status = child.WaitFor(std::chrono::seconds(60));
  if (!status) return {-1, "timeout"};
  return {status->signaled ? -status->code : status->code, files::testing::ReadFile(out)};
}

}  // namespace srics::launcher::testing

#endif  // SRICS_TESTS_DEPLOY_LAUNCHER_SWEEP_TESTING_H_
