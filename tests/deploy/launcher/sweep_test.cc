// `srics sweep`: the plan and its checks, the outcome a run folder records, the exit codes of
// bad methods. The sweep stopped half-way and resumed is in sweep_resume_test.cc (slow).

#include "deploy/launcher/sweep.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

#include "common/config/config.h"
#include "common/config/config_error.h"
#include "deploy/launcher/child_process.h"
#include "deploy/launcher/command_line.h"
#include "deploy/launcher/run_folder.h"
#include "deploy/run_folder/outcome.h"
#include "tests/common/config/config_files.h"
#include "tests/common/files/test_files.h"
#include "tests/deploy/launcher/sweep_testing.h"

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;
using files::testing::ReadFile;
using ::testing::HasSubstr;
using testing::kConfig;
using testing::kTinyRun;
using ::testing::Not;
using testing::RunSrics;

class SweepTest : public ::testing::Test {
 protected:
  SweepOptions Options(std::vector<std::string> methods, std::vector<uint64_t> seeds) const {
    SweepOptions o;
    o.config_file = kConfig;
    o.methods = std::move(methods);
    o.seeds = std::move(seeds);
    o.overrides = kTinyRun;
    o.out_dir = (root_ / "sweep").string();
    o.in_process = true;
    return o;
  }

  files::testing::ScratchFolder root_{"srics_sweep_test"};
};

TEST_F(SweepTest, ParsesTheGridAndRefusesBadArguments) {
  const SweepOptions o = ParseSweepArgs(
      {"c.yaml", "--methods", "srics,smorl", "--seeds", "1,3-4", "--set", "a.b=1", "--in-process", "--parallel", "2"});
  EXPECT_EQ(o.methods, (std::vector<std::string>{"srics", "smorl"}));
  EXPECT_EQ(o.seeds, (std::vector<uint64_t>{1, 3, 4}));
  EXPECT_EQ(o.overrides, std::vector<std::string>{"a.b=1"});
  EXPECT_TRUE(o.in_process);
  EXPECT_EQ(o.parallel, 2);
  EXPECT_THROW(ParseSweepArgs({"c.yaml", "--seeds", "1"}), std::invalid_argument);        // no methods
  EXPECT_THROW(ParseSweepArgs({"c.yaml", "--methods", "srics"}), std::invalid_argument);  // no seeds
  EXPECT_THROW(ParseSweepArgs({"c.yaml", "--methods", "a,a", "--seeds", "1"}), std::invalid_argument);
  EXPECT_THROW(ParseSweepArgs({"c.yaml", "--methods", "a", "--seeds", "x"}), std::invalid_argument);
  EXPECT_THROW(ParseSweepArgs({"c.yaml", "--methods", "a", "--seeds", "1", "--parallel", "0"}), std::invalid_argument);
}

// `srics learn-graph --seed N --set K=V`: --set assigned its values to the whole override list
// and dropped the seed put there before, so every seed learned seed 1's graph (the graph
// acceptance with --set ran three identical seeds). The seed now comes last, in either order.
TEST(LearnGraphArgsTest, TheSeedSurvivesSetOverrides) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"--env", "e.yaml", "--seed", "2", "--out", "d", "--set", "a.b=1", "--set", "c=2"},
           {"--env", "e.yaml", "--set", "a.b=1", "--set", "c=2", "--seed", "2", "--out", "d"}}) {
    EXPECT_EQ(ParseLearnGraphArgs(args).overrides, (std::vector<std::string>{"a.b=1", "c=2", "run.seed=2"}));
  }
  EXPECT_EQ(ParseLearnGraphArgs({"--env", "e.yaml", "--out", "d"}).overrides, std::vector<std::string>{});
}

// `srics learn-graph --evidence`: the random-action data's tie evidence and the graph by
// construction, then a stop before any training (no graph published). Random table 9 ties
// pucks 1 and 3 with a rope: in 60 episodes each end starts at a distance only while the other
// moves (the counts by mover equal the counts per object), and no other object does: the pair is
// named, and the read-out's bars for object pairs are printed (off when set to 0).
TEST_F(SweepTest, LearnGraphEvidencePrintsTheDatasTieEvidenceAndStopsBeforeTraining) {
  const auto [code, text] =
      RunSrics(root_, {"learn-graph", "--random-table", "9", "--seed", "1", "--out", (root_ / "evidence").string(),
                       "--evidence", "--set", "graph.episodes=60"});
  ASSERT_EQ(code, 0) << text;
  const std::regex evidence(
      R"(at a distance \(per entity[^)]*\): 0: 0 1: (\d+) 2: 0 3: (\d+) 4: 0\n)"
      R"(  \.\.\. while another object moves \(i->j: j starts while i moves\): 1->3: (\d+) 3->1: (\d+)\n)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, evidence)) << text;
  EXPECT_GT(std::stoi(m[1]), 0);
  EXPECT_EQ(m[2], m[3]) << "puck 3 started while puck 1 moved";
  EXPECT_EQ(m[1], m[4]) << "puck 1 started while puck 3 moved";
  EXPECT_THAT(text, HasSubstr("by construction: action->0, 0->1, 0->3, 1->3, 3->1\n"));
  EXPECT_THAT(text, Not(HasSubstr("published graph")));
  EXPECT_THAT(text, HasSubstr("tied by that evidence (their edges' KL times graph.tie_kl_factor): 1 <-> 3\n"));
  EXPECT_THAT(text, HasSubstr("object pairs' bars: 0.02 for a pair tied by that evidence, 0.12 for any other "
                              "(the arm's edges 0.06)\n"));
  const auto [off_code, off] =
      RunSrics(root_, {"learn-graph", "--random-table", "9", "--seed", "1", "--out", (root_ / "off").string(),
                       "--evidence", "--set", "graph.episodes=60", "--set", "graph.tied_pair_threshold=0", "--set",
                       "graph.untied_pair_threshold=0"});
  ASSERT_EQ(off_code, 0) << off;
  EXPECT_THAT(off, HasSubstr("object pairs' bars: none (off): every edge above 0.06\n"));
}

TEST_F(SweepTest, PlansOneRunFolderPerMethodAndSeedWithItsOwnRunId) {
  const SweepPlan plan = PlanSweep(Options({"srics", "smorl"}, {1, 2}));
  ASSERT_EQ(plan.runs.size(), 4u);
  EXPECT_EQ(plan.runs[0].name, "srics-seed1");
  EXPECT_EQ(plan.runs[3].name, "smorl-seed2");
  EXPECT_EQ(plan.runs[3].dir, (root_ / "sweep" / "smorl-seed2").string());
  EXPECT_THAT(plan.runs[3].effective_yaml, HasSubstr("method: smorl"));
  EXPECT_THAT(plan.runs[3].effective_yaml, HasSubstr("seed: 2"));
  EXPECT_NE(plan.runs[0].effective_yaml, plan.runs[1].effective_yaml);
  EXPECT_THAT(plan.runs[1].overrides.back(), HasSubstr("-srics-seed2"));  // transport.run_id
  // the manifest does not depend on the order the grid was typed in
  EXPECT_EQ(PlanSweep(Options({"smorl", "srics"}, {2, 1})).manifest, plan.manifest);
}

TEST_F(SweepTest, AnUnknownMethodIsAConfigErrorNamingRunMethod) {
  try {
    PlanSweep(Options({"srics", "no_such_method"}, {1}));
    FAIL() << "no error";
  } catch (const config::ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("run.method"));
    EXPECT_THAT(e.what(), HasSubstr("no_such_method"));
  }
  SweepOptions o = Options({"srics"}, {1});
  o.overrides.push_back("run.seed=7");
  EXPECT_THROW(PlanSweep(o), std::invalid_argument) << "the sweep sets run.seed itself";
}

TEST_F(SweepTest, AnotherGridOrAChangedConfigInTheSameFolderIsRefused) {
  const SweepPlan plan = PlanSweep(Options({"srics", "smorl"}, {1}));
  CheckSweepFolder(plan);
  EXPECT_THAT(ReadFile(root_ / "sweep" / "sweep.yaml"), HasSubstr("methods: [smorl, srics]"));
  CheckSweepFolder(plan);  // the same grid again: fine
  try {
    CheckSweepFolder(PlanSweep(Options({"srics", "smorl"}, {1, 2})));
    FAIL() << "another grid was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("holds another grid"));
    EXPECT_THAT(e.what(), HasSubstr("seeds: [1]"));
  }
  // a run folder whose configuration is not what the run would get now
  fs::create_directories(plan.runs[0].dir);
  std::ofstream(plan.runs[0].dir + "/config.yaml") << "# header\n" << plan.runs[0].effective_yaml << "\n";
  CheckSweepFolder(plan);
  std::ofstream(plan.runs[0].dir + "/config.yaml") << "# header\n" << plan.runs[1].effective_yaml << "\n";
  try {
    CheckSweepFolder(plan);
    FAIL() << "a changed configuration was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("changed since it started"));
  }
}

// Issue 15: two sweeps of the same grid on one host (transport.run_id: auto) must not share
// run ids; a run resumed in its folder keeps the id it started with.
TEST_F(SweepTest, TwoSweepLaunchesGetDifferentRunIdsAndAResumedRunKeepsItsOwn) {
  auto run_id = [](const SweepRun& run) {
    const std::string& last = run.overrides.back();
    EXPECT_EQ(last.rfind("transport.run_id=", 0), 0u) << last;
    return last.substr(last.find('=') + 1);
  };
  const SweepPlan first = PlanSweep(Options({"srics", "smorl"}, {1}));
  const SweepPlan second = PlanSweep(Options({"srics", "smorl"}, {1}));
  EXPECT_NE(run_id(first.runs[0]), run_id(second.runs[0]));
  EXPECT_NE(run_id(first.runs[0]), run_id(first.runs[1]));
  EXPECT_THAT(run_id(first.runs[0]), HasSubstr("-srics-seed1"));
  // the first launch's run 0 started: its folder records its id, which the next launch keeps
  CheckSweepFolder(first);
  fs::create_directories(first.runs[0].dir);
  std::ofstream(first.runs[0].dir + "/config.yaml") << "# header\n" << first.runs[0].effective_yaml << "\n";
  const SweepPlan resumed = PlanSweep(Options({"srics", "smorl"}, {1}));
  EXPECT_EQ(run_id(resumed.runs[0]), run_id(first.runs[0]));
  EXPECT_NE(run_id(resumed.runs[1]), run_id(first.runs[1])) << "a run that never started gets this launch's id";
  EXPECT_NO_THROW(CheckSweepFolder(resumed));
}

// A sweep resumed after a default changed (config::EarlierDefaults): a run folder whose record
// lacks the key is planned with the value it ran with and passes the check; its own srics run
// adds that value (run_folder.h), so the sweep passes on only the grid's overrides.
TEST_F(SweepTest, ARunFromBeforeADefaultChangedIsPlannedWithTheValueItHad) {
  const SweepPlan first = PlanSweep(Options({"srics"}, {1}));
  CheckSweepFolder(first);
  PrepareRunFolder(config::LoadConfig(kConfig, first.runs[0].overrides), first.runs[0].dir);
  const std::string record = ReadFile(fs::path(first.runs[0].dir) / "resolved-config.yaml");
  std::ofstream(first.runs[0].dir + "/resolved-config.yaml")
      << config::testing::WithoutRecordedKeys(record, {"tie_kl_factor"});
  const SweepPlan resumed = PlanSweep(Options({"srics"}, {1}));
  EXPECT_THAT(resumed.runs[0].resolved_yaml, HasSubstr("tie_kl_factor: 1\n"));
  EXPECT_THAT(first.runs[0].resolved_yaml, HasSubstr("tie_kl_factor: 0.5\n"));
  EXPECT_NO_THROW(CheckSweepFolder(resumed));
  EXPECT_EQ(resumed.runs[0].overrides, first.runs[0].overrides);
  EXPECT_THROW(CheckSweepFolder(first), std::invalid_argument) << "the new default handed to the old run";
}

TEST_F(SweepTest, RunFinishedOnlyWhenTheOutcomeSaysSo) {
  const std::string dir = (root_ / "run").string();
  fs::create_directories(dir);
  EXPECT_FALSE(run_folder::RunFinished(dir));
  run_folder::WriteRunOutcome(dir, {"interrupted", 130, "interrupted"});
  EXPECT_FALSE(run_folder::RunFinished(dir));
  run_folder::WriteRunOutcome(dir, {"finished", 0, "the \"budget\" is done"});
  EXPECT_TRUE(run_folder::RunFinished(dir));
  EXPECT_EQ(run_folder::ReadRunOutcome(dir)->reason, "the \"budget\" is done");
  EXPECT_LT(run_folder::ReadRunOutcome(dir)->cpu_seconds, 0);  // not given: not written, not known
  run_folder::WriteRunOutcome(dir, {"finished", 0, "done", 4321.4});
  EXPECT_EQ(run_folder::ReadRunOutcome(dir)->cpu_seconds, 4321);
  run_folder::RemoveRunOutcome(dir);
  EXPECT_FALSE(run_folder::RunFinished(dir));
}

TEST_F(SweepTest, UnknownMethodsExitWithCode2NamingTheKey) {
  const auto [sweep_code, sweep_text] =
      RunSrics(root_, {"sweep", kConfig, "--methods", "srics,hacc", "--seeds", "1", "--out", (root_ / "s").string()});
  EXPECT_EQ(sweep_code, 2) << sweep_text;
  EXPECT_THAT(sweep_text, HasSubstr("run.method"));
  EXPECT_FALSE(fs::exists(root_ / "s")) << "nothing starts on a bad grid";
  const auto [run_code, run_text] = RunSrics(
      root_, {"run", kConfig, "--in-process", "--set", "run.method=hacc", "--run-dir", (root_ / "r").string()});
  EXPECT_EQ(run_code, 2) << run_text;
  EXPECT_THAT(run_text, HasSubstr("run.method"));
}

}  // namespace
}  // namespace srics::launcher
