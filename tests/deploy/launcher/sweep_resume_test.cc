// A sweep of two tiny in-process runs stopped half-way by Ctrl-C and run again: the finished
// run is not repeated (its files untouched), the stopped one resumes from its checkpoint with
// the replay it had and finishes; a third start skips both, another grid is refused.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <thread>

#include "common/config/config.h"
#include "deploy/launcher/child_process.h"
#include "deploy/launcher/run_folder.h"
#include "deploy/launcher/sweep.h"
#include "deploy/run_folder/outcome.h"
#include "learner/learner.h"
#include "tests/common/files/test_files.h"
#include "tests/deploy/launcher/sweep_testing.h"

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;
using files::testing::ReadFile;
using ::testing::HasSubstr;
using testing::kConfig;
using testing::kTinyRun;
using testing::RunSrics;

class SweepResumeTest : public ::testing::Test {
 protected:
  files::testing::ScratchFolder root_{"srics_sweep_resume_test"};
};

// The learner's checkpoint of a run folder, loaded as a resumed learner would.
std::unique_ptr<learner::Learner> LoadLearner(const std::string& run_dir) {
  const config::Config config = config::LoadConfig(run_dir + "/config.yaml", {});
  auto learner = std::make_unique<learner::Learner>(learner::LearnerOptionsFor(config, rl::RunShapeFor(config)));
  learner->LoadCheckpoint(run_dir + "/checkpoint.srics");
  return learner;
}

TEST_F(SweepResumeTest, AStoppedSweepResumesWithoutRepeatingFinishedRunsAndKeepsTheReplay) {
  const fs::path sweep = root_ / "sweep";
  std::vector<std::string> argv = {SRICS_LAUNCHER, "sweep", kConfig,        "--methods", "srics,smorl", "--seeds", "1",
                                   "--in-process", "--out", sweep.string(), "--display", "none"};
  for (const std::string& o : kTinyRun) argv.insert(argv.end(), {"--set", o});
  // stopped once the first run has finished and the second has checkpointed
  const std::string first = (sweep / "srics-seed1").string(), second = (sweep / "smorl-seed1").string();

  ChildProcess child = ChildProcess::Spawn(argv, {.output_file = (root_ / "first.out").string()});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(240);
  while (!(run_folder::RunFinished(first) && fs::exists(second + "/checkpoint.srics")) &&
         std::chrono::steady_clock::now() < deadline && child.running()) {
    child.Poll();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(run_folder::RunFinished(first)) << ReadFile(root_ / "first.out");
  ASSERT_TRUE(fs::exists(second + "/checkpoint.srics")) << ReadFile(root_ / "first.out");
  ASSERT_FALSE(run_folder::RunFinished(second)) << "the second run ended before the sweep could be stopped";
  child.Signal(SIGINT);  // Ctrl-C
  const auto stopped = child.WaitFor(std::chrono::seconds(60));
  ASSERT_TRUE(stopped);
  EXPECT_EQ(stopped->code, 130) << ReadFile(root_ / "first.out");
  ASSERT_TRUE(run_folder::ReadRunOutcome(second));
  EXPECT_EQ(run_folder::ReadRunOutcome(second)->state, "interrupted");

  // what was there when it stopped
  const std::string first_eval = ReadFile(first + "/eval.csv");
  const auto first_eval_time = fs::last_write_time(first + "/eval.csv");
  const std::string first_checkpoint = ReadFile(first + "/checkpoint.srics");
  uint64_t replay_at_stop = 0, updates_at_stop = 0, steps_at_stop = 0;
  {
    const auto stopped_learner = LoadLearner(second);
    replay_at_stop = stopped_learner->replay().transitions();
    updates_at_stop = stopped_learner->counters().updates;
    steps_at_stop = stopped_learner->counters().training_env_steps;
  }
  EXPECT_GT(replay_at_stop, 0u) << "the checkpoint keeps the replay";
  ASSERT_LT(steps_at_stop, 1500u);

  // the same command again
  ChildProcess again = ChildProcess::Spawn(argv, {.output_file = (root_ / "second.out").string()});
  const auto done = again.WaitFor(std::chrono::seconds(240));
  ASSERT_TRUE(done) << ReadFile(root_ / "second.out");
  EXPECT_EQ(done->code, 0) << ReadFile(root_ / "second.out");
  const std::string output = ReadFile(root_ / "second.out");
  EXPECT_THAT(output, HasSubstr("run 1 of 2 srics-seed1: finished earlier, skipped"));
  EXPECT_THAT(output, HasSubstr("run 2 of 2 smorl-seed1: resuming from its checkpoint"));
  // the finished run was not touched
  EXPECT_EQ(ReadFile(first + "/eval.csv"), first_eval);
  EXPECT_EQ(fs::last_write_time(first + "/eval.csv"), first_eval_time);
  EXPECT_EQ(ReadFile(first + "/checkpoint.srics"), first_checkpoint);
  // the stopped run resumed from its checkpoint with the replay it had, and finished
  EXPECT_TRUE(run_folder::RunFinished(second));
  const std::string log = ReadFile(second + "/logs/launcher.log");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(log, m,
                                std::regex("resumed from \\S+: (\\d+) updates, \\d+ transitions inserted, "
                                           "policy v\\d+, replay (\\d+) transitions")))
      << log;
  EXPECT_EQ(std::stoull(m[1]), updates_at_stop);
  EXPECT_EQ(std::stoull(m[2]), replay_at_stop);
  const auto final_learner = LoadLearner(second);
  EXPECT_GE(final_learner->counters().training_env_steps, 1500u);
  EXPECT_GT(final_learner->counters().updates, updates_at_stop);
  // its actor went on with new episode ids (a second generation)
  EXPECT_EQ(ReadFile(second + "/state/actor-0.generation"), "2\n");

  // everything done: a third start skips both; another grid into the folder is refused
  const auto [code, text] = RunSrics(root_, std::vector<std::string>(argv.begin() + 1, argv.end()));
  EXPECT_EQ(code, 0) << text;
  EXPECT_THAT(text, HasSubstr("2 of 2 runs finished"));
  std::vector<std::string> other(argv.begin() + 1, argv.end());
  other[5] = "1,2";  // --seeds
  const auto [other_code, other_text] = RunSrics(root_, other);
  EXPECT_EQ(other_code, 2);
  EXPECT_THAT(other_text, HasSubstr("holds another grid"));
}

}  // namespace
}  // namespace srics::launcher
