#pragma once
// What the sweep tests share: the tiny runs they sweep and the srics program as a child.

#include <chrono>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "deploy/launcher/child_process.h"
#include "tests/common/files/test_files.h"
#include "tests/deploy/tiny_run.h"

namespace srics::launcher::testing {

inline const std::string kConfig = std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml";

// Runs of a few seconds: a graph from 20 episodes and 40 GNN updates, 1500 training steps.
inline const std::vector<std::string> kTinyRun =
    srics::testing::TinyRunSettings({"run.total_env_steps=1500", "learner.checkpoint_every_updates=100",
                                     "actors.count=1", "actors.eval_every_env_steps=500"});

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
