// A run on "two hosts" of one machine: two `srics run --roles` launchers over loopback DDS,
// one with the graph service and the learner, one with the actors (the real role programs,
// a tiny budget). Each supervises only its share, sees the whole run on its display and in
// its CSV files, and both end by themselves when the budget is done.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "deploy/launcher/child_process.h"
#include "deploy/launcher/command_line.h"
#include "tests/common/files/test_files.h"
#include "tests/deploy/launcher/sweep_testing.h"

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;
using files::testing::ReadFile;
using ::testing::HasSubstr;

TEST(RolesArgsTest, RolesAndActorIdsOfAHostsShare) {
  LaunchOptions o = ParseRunArgs({"c.yaml", "--roles", "learner,graph"});
  EXPECT_EQ(o.roles, (std::vector<std::string>{"learner", "graph"}));
  config::Config config;
  config.actors.count = 3;
  RoleShare share = ShareOf(o, config);
  EXPECT_TRUE(share.graph && share.learner);
  EXPECT_TRUE(share.actor_ids.empty());
  EXPECT_FALSE(share.whole_run);

  o = ParseRunArgs({"c.yaml", "--roles", "actor", "--ids", "2-5,7"});
  share = ShareOf(o, config);
  EXPECT_FALSE(share.graph || share.learner);
  EXPECT_EQ(share.actor_ids, (std::vector<int>{2, 3, 4, 5, 7}));

  share = ShareOf(ParseRunArgs({"c.yaml", "--roles", "actor"}), config);
  EXPECT_EQ(share.actor_ids, (std::vector<int>{0, 1, 2})) << "every actor of the config";
  share = ShareOf(ParseRunArgs({"c.yaml"}), config);
  EXPECT_TRUE(share.whole_run && share.graph && share.learner);
  EXPECT_EQ(share.actor_ids.size(), 3u);

  for (const std::vector<std::string>& bad :
       std::vector<std::vector<std::string>>{{"c.yaml", "--roles", "learner,critic"},
                                             {"c.yaml", "--roles", "actor,actor"},
                                             {"c.yaml", "--roles", "learner", "--ids", "1"},
                                             {"c.yaml", "--ids", "1"},
                                             {"c.yaml", "--roles", "actor", "--ids", "3-1"},
                                             {"c.yaml", "--roles", "actor", "--ids", "x"}}) {
    try {
      ParseRunArgs(bad);
      ADD_FAILURE() << "accepted: " << ::testing::PrintToString(bad);
    } catch (const std::invalid_argument& e) {
      EXPECT_THAT(e.what(), ::testing::AnyOf(HasSubstr("--roles"), HasSubstr("--ids"))) << e.what();
    }
  }
}

class RolesTest : public ::testing::Test {
 protected:
  void SetUp() override { root_ = files::testing::FreshFolder("srics_roles_test"); }
  void TearDown() override { fs::remove_all(root_); }

  // `srics run CONFIG --roles ...` for one host of the run
  ChildProcess StartHost(const std::string& host, std::vector<std::string> share) {
    std::vector<std::string> argv = {SRICS_LAUNCHER, "run",   testing::kConfig, "--run-dir", (root_ / host).string(),
                                     "--display",    "plain", "--stop-timeout", "20"};
    argv.insert(argv.end(), share.begin(), share.end());
    std::vector<std::string> sets = testing::kTinyRun;
    sets.insert(sets.end(), {"actors.count=2", "transport.run_id=roles-test-" + std::to_string(getpid()),
                             "transport.domain_id=" + std::to_string(100 + getpid() % 50)});
    for (const std::string& s : sets) argv.insert(argv.end(), {"--set", s});
    return ChildProcess::Spawn(
        argv,
        {.output_file = (root_ / (host + ".out")).string(), .own_process_group = true, .parent_death_signal = SIGKILL});
  }

  fs::path root_;
};

TEST_F(RolesTest, AShareOfARunNeedsAnExplicitRunId) {
  const auto [code, output] =
      testing::RunSrics(root_, {"run", testing::kConfig, "--roles", "actor", "--run-dir", (root_ / "b").string()});
  EXPECT_EQ(code, 2) << output;
  EXPECT_THAT(output, HasSubstr("--roles"));
  EXPECT_THAT(output, HasSubstr("transport.run_id"));
  EXPECT_FALSE(fs::exists(root_ / "b")) << "nothing started";
}

TEST_F(RolesTest, TwoHostsRunTheirSharesAndBothSeeTheRunToItsEnd) {
  ChildProcess a = StartHost("a", {"--roles", "learner,graph"});
  ChildProcess b = StartHost("b", {"--roles", "actor", "--ids", "0-1"});
  const auto exit_a = a.WaitFor(std::chrono::minutes(6));
  const auto exit_b = b.WaitFor(std::chrono::minutes(1));
  const std::string out_a = ReadFile(root_ / "a.out"), out_b = ReadFile(root_ / "b.out");
  ASSERT_TRUE(exit_a.has_value()) << out_a;
  ASSERT_TRUE(exit_b.has_value()) << out_b;
  EXPECT_EQ(exit_a->Describe(), "exit code 0") << out_a;
  EXPECT_EQ(exit_b->Describe(), "exit code 0") << out_b;

  // each host started only its share
  const fs::path a_dir = root_ / "a", b_dir = root_ / "b";
  for (const char* log : {"logs/graph.out", "logs/learner.out", "checkpoint.srics", "graph.json"})
    EXPECT_TRUE(fs::exists(a_dir / log)) << log;
  for (const char* log : {"logs/actor-0.out", "logs/actor-1.out"}) {
    EXPECT_FALSE(fs::exists(a_dir / log)) << log;
    EXPECT_TRUE(fs::exists(b_dir / log)) << log;
  }
  for (const char* log : {"logs/graph.out", "logs/learner.out"}) EXPECT_FALSE(fs::exists(b_dir / log)) << log;

  // both saw the run progress: the learner's stats and the actors' evaluations reached both
  for (const fs::path& dir : {a_dir, b_dir}) {
    const std::string eval = ReadFile(dir / "eval.csv"), learner = ReadFile(dir / "learner.csv");
    EXPECT_GE(std::count(eval.begin(), eval.end(), '\n'), 3) << dir << "/eval.csv:\n" << eval;
    EXPECT_GE(std::count(learner.begin(), learner.end(), '\n'), 3) << dir << "/learner.csv";
    EXPECT_THAT(ReadFile(dir / "outcome.yaml"), HasSubstr("finished")) << dir;
  }
  EXPECT_THAT(out_b, HasSubstr("steps ")) << "plain progress lines";
  EXPECT_THAT(ReadFile(a_dir / "logs/launcher.log"), HasSubstr("stopping: the budget is done"));
  EXPECT_THAT(ReadFile(b_dir / "logs/launcher.log"), HasSubstr("stopping: the budget is done"));
  EXPECT_THAT(ReadFile(b_dir / "logs/launcher.log"), ::testing::Not(HasSubstr("restarted")));
  // each host plays the passive baseline itself (issue 39), the one without actors too, and
  // takes the actors' as the run's: none refused
  for (const fs::path& dir : {a_dir, b_dir}) {
    const std::string summary = ReadFile(dir / "summary.txt");
    EXPECT_THAT(summary, HasSubstr("passive   object distance")) << dir << "/summary.txt:\n" << summary;
    EXPECT_THAT(summary, ::testing::Not(HasSubstr("refused"))) << dir << "/summary.txt:\n" << summary;
    EXPECT_THAT(ReadFile(dir / "logs/launcher.log"), HasSubstr("passive baseline played here")) << dir;
  }
}

}  // namespace
}  // namespace srics::launcher
