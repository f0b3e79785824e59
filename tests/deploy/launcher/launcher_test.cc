// `srics run` driving stand-in roles: fake_child linked under the names srics-graph,
// srics-learner and srics-actor (behaviour chosen by FAKE_* environment variables, which the
// launcher's children inherit). The launcher's own DDS participant runs on a test domain.

#include "deploy/launcher/launcher.h"

#include <errno.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "common/config/config.h"
#include "common/transport/transport.h"
#include "deploy/launcher/child_process.h"
#include "deploy/launcher/command_line.h"
#include "tests/common/files/test_files.h"
#include "tests/deploy/tiny_run.h"
#include "tests/sanitizer.h"

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using ::testing::HasSubstr;
using ::testing::Not;

using files::testing::ReadFile;

// pids a stand-in printed ("start <pid>") in its output file
std::vector<pid_t> StartedPids(const fs::path& output_file) {
  std::vector<pid_t> pids;
  std::ifstream in(output_file);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("start ", 0) == 0) pids.push_back(std::atoi(line.c_str() + 6));
  return pids;
}

bool ProcessExists(pid_t pid) { return kill(pid, 0) == 0 || errno != ESRCH; }

class LauncherTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(root_ / "bin");
    for (const char* name : {"srics-graph", "srics-learner", "srics-actor"})
      fs::create_symlink(FAKE_CHILD, root_ / "bin" / name);
    run_dir_ = root_ / "run";
  }
  void TearDown() override {
    for (const char* var : {"FAKE_GRAPH", "FAKE_LEARNER", "FAKE_ACTOR", "FAKE_ACTOR_0"}) unsetenv(var);
  }

  ChildProcess StartLauncher(std::vector<std::string> extra = {}, bool with_run_id = true,
                             std::string config = std::string(SRICS_SOURCE_DIR) +
                                                  "/deploy/configs/rearrange-1-cpu.yaml",
                             const std::string& output = "launcher.out") {
    std::vector<std::string> argv = {SRICS_LAUNCHER,
                                     "run",
                                     config,
                                     "--actors",
                                     "2",
                                     "--bin-dir",
                                     (root_ / "bin").string(),
                                     "--run-dir",
                                     run_dir_.string(),
                                     "--display",
                                     "plain",
                                     "--stop-timeout",
                                     "5",
                                     "--set",
                                     "transport.domain_id=" + std::to_string(150 + getpid() % 50)};
    if (with_run_id) argv.insert(argv.end(), {"--set", "transport.run_id=launcher-test-" + std::to_string(getpid())});
    argv.insert(argv.end(), extra.begin(), extra.end());
    return ChildProcess::Spawn(
        argv, {.output_file = (root_ / output).string(), .own_process_group = true, .parent_death_signal = SIGKILL});
  }

  // every role's pid over all incarnations
  std::vector<pid_t> RolePids() const {
    std::vector<pid_t> pids;
    for (const char* name : {"graph", "learner", "actor-0", "actor-1"})
      for (pid_t pid : StartedPids(run_dir_ / "logs" / (std::string(name) + ".out"))) pids.push_back(pid);
    return pids;
  }

  // `launcher` exits 2 (a usage error) saying `what`, before it starts a role or makes its run
  // folder.
  void ExpectUsageExitSaying(ChildProcess& launcher, const std::string& what) {
    const auto exit = launcher.WaitFor(milliseconds(20000));
    ASSERT_TRUE(exit.has_value());
    EXPECT_EQ(exit->Describe(), "exit code 2");
    EXPECT_THAT(ReadFile(root_ / "launcher.out"), HasSubstr(what));
    EXPECT_FALSE(fs::exists(run_dir_));
  }

  files::testing::ScratchFolder root_{"srics_launcher_test"};
  fs::path run_dir_;
};

TEST(ParseRunArgsTest, ActorsBecomeAnOverrideAndBadValuesAreRejected) {
  LaunchOptions options = ParseRunArgs({"cfg.yaml", "--actors", "3", "--set", "run.seed=4", "--display", "none"});
  EXPECT_EQ(options.config_file, "cfg.yaml");
  EXPECT_EQ(options.actors, 3);
  EXPECT_EQ(options.overrides, (std::vector<std::string>{"run.seed=4", "actors.count=3"}));
  EXPECT_EQ(options.display, DisplayMode::kNone);
  EXPECT_THROW(ParseRunArgs({}), std::invalid_argument);
  EXPECT_THROW(ParseRunArgs({"cfg.yaml", "--actors", "0"}), std::invalid_argument);
  EXPECT_THROW(ParseRunArgs({"cfg.yaml", "--actors"}), std::invalid_argument);
  EXPECT_THROW(ParseRunArgs({"cfg.yaml", "--display", "fancy"}), std::invalid_argument);
  EXPECT_THROW(ParseRunArgs({"cfg.yaml", "--frobnicate"}), std::invalid_argument);
}

TEST(ParseRunArgsTest, HttpTakesAPortAndItsBindAddress) {
  EXPECT_EQ(ParseRunArgs({"cfg.yaml"}).http_port, -1);  // no dashboard unless asked
  const LaunchOptions options = ParseRunArgs({"cfg.yaml", "--http", "8080", "--http-bind", "0.0.0.0"});
  EXPECT_EQ(options.http_port, 8080);
  EXPECT_EQ(options.http_bind, "0.0.0.0");
  EXPECT_EQ(ParseRunArgs({"cfg.yaml", "--http", "8080"}).http_bind, "127.0.0.1");
  EXPECT_EQ(ParseRunArgs({"cfg.yaml", "--http", "0"}).http_port, 0);
  EXPECT_THROW(ParseRunArgs({"cfg.yaml", "--http", "70000"}), std::invalid_argument);
  EXPECT_THROW(ParseRunArgs({"cfg.yaml", "--http", "-1"}), std::invalid_argument);
  EXPECT_THROW(ParseRunArgs({"cfg.yaml", "--http"}), std::invalid_argument);
  EXPECT_THROW(ParseRunArgs({"cfg.yaml", "--http-bind", "0.0.0.0"}), std::invalid_argument);  // without --http
}

TEST_F(LauncherTest, RunEndsWhenLearnerAndActorsFinishAndACrashedActorIsRestarted) {
  // the lead's protocol: the learner exits 0 at the budget, then the actors (after a last
  // evaluation); actor 0 crashes once on the way
  setenv("FAKE_LEARNER", "exit0-after:3000", 1);
  setenv("FAKE_ACTOR", "exit0-after:4000", 1);
  setenv("FAKE_ACTOR_0", ("crash-once:" + (root_ / "marker").string() + ":3:4000").c_str(), 1);
  ChildProcess launcher = StartLauncher();
  const auto exit = launcher.WaitFor(milliseconds(60000));
  ASSERT_TRUE(exit.has_value()) << ReadFile(root_ / "launcher.out");
  EXPECT_EQ(exit->Describe(), "exit code 0") << ReadFile(root_ / "launcher.out");

  // the run folder
  EXPECT_THAT(ReadFile(run_dir_ / "config.yaml"), HasSubstr("count: 2"));
  for (const char* file : {"eval.csv", "learner.csv", "nodes.csv", "summary.txt", "logs/launcher.log"})
    EXPECT_TRUE(fs::exists(run_dir_ / file)) << file;
  const std::string log = ReadFile(run_dir_ / "logs/launcher.log");
  EXPECT_THAT(log, HasSubstr("actor-0 ended: exit code 3; restart 1 in 1.0s"));
  EXPECT_THAT(log, HasSubstr("actor-0 restarted"));
  EXPECT_THAT(log, HasSubstr("the learner finished its budget; waiting for the actors"));
  EXPECT_THAT(log, HasSubstr("stopping: the budget is done"));
  EXPECT_THAT(log, HasSubstr("graph stopped: exit code 0"));  // the service runs until told
  EXPECT_EQ(StartedPids(run_dir_ / "logs/actor-0.out").size(), 2u);
  EXPECT_EQ(StartedPids(run_dir_ / "logs/actor-1.out").size(), 1u);
  // children got the effective config and the run folder
  EXPECT_THAT(ReadFile(root_ / "launcher.out"), HasSubstr("run finished: the budget is done; restarts 1"));
  for (pid_t pid : RolePids()) EXPECT_FALSE(ProcessExists(pid)) << pid;
}

TEST_F(LauncherTest, ActorsThatDoNotFinishAreStoppedAfterTheGracePeriod) {
  setenv("FAKE_LEARNER", "exit0-after:1000", 1);
  ChildProcess launcher = StartLauncher({"--final-eval-grace", "1"});
  const auto exit = launcher.WaitFor(milliseconds(30000));
  ASSERT_TRUE(exit.has_value());
  EXPECT_EQ(exit->Describe(), "exit code 0") << ReadFile(root_ / "launcher.out");
  const std::string log = ReadFile(run_dir_ / "logs/launcher.log");
  EXPECT_THAT(log, HasSubstr("stopping: the budget is done (actors did not finish within the grace period)"));
  EXPECT_THAT(log, HasSubstr("actor-1 stopped: exit code 0"));
  for (pid_t pid : RolePids()) EXPECT_FALSE(ProcessExists(pid)) << pid;
}

TEST_F(LauncherTest, SigintStopsEveryChildAndExits130) {
  ChildProcess launcher = StartLauncher();
  // wait until all four roles run
  const auto deadline = std::chrono::steady_clock::now() + milliseconds(20000);
  while (RolePids().size() < 4 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(milliseconds(50));
  const std::vector<pid_t> pids = RolePids();
  ASSERT_EQ(pids.size(), 4u) << ReadFile(root_ / "launcher.out");
  std::this_thread::sleep_for(milliseconds(200));

  launcher.Signal(SIGINT);
  const auto start = std::chrono::steady_clock::now();
  const auto exit = launcher.WaitFor(milliseconds(15000));
  ASSERT_TRUE(exit.has_value());
  EXPECT_LT(std::chrono::steady_clock::now() - start, milliseconds(5000));
  EXPECT_EQ(exit->Describe(), "exit code 130") << ReadFile(root_ / "launcher.out");
  for (pid_t pid : pids) EXPECT_FALSE(ProcessExists(pid)) << pid;
  const std::string log = ReadFile(run_dir_ / "logs/launcher.log");
  for (const char* name : {"graph", "learner", "actor-0", "actor-1"})
    EXPECT_THAT(log, HasSubstr(std::string(name) + " stopped: exit code 0"));
  EXPECT_THAT(ReadFile(root_ / "launcher.out"), HasSubstr("run interrupted"));
}

TEST_F(LauncherTest, BadConfigExitsWithCode2BeforeStartingAnything) {
  ChildProcess launcher = StartLauncher({"--set", "run.total_env_steps=lots"});
  ExpectUsageExitSaying(launcher, "run.total_env_steps");
}

TEST_F(LauncherTest, UnknownMethodExitsWithCode2NamingRunMethod) {
  ChildProcess launcher = StartLauncher({"--set", "run.method=feudal"});
  ExpectUsageExitSaying(launcher, "run.method: expected one of");
}

TEST_F(LauncherTest, MissingRoleProgramIsNamed) {
  fs::remove(root_ / "bin" / "srics-learner");
  ChildProcess launcher = StartLauncher();
  const auto exit = launcher.WaitFor(milliseconds(20000));
  ASSERT_TRUE(exit.has_value());
  EXPECT_EQ(exit->Describe(), "exit code 1");
  EXPECT_THAT(ReadFile(root_ / "launcher.out"), HasSubstr("cannot find the program srics-learner"));
}

// Issue 15: two runs launched with the default run id on one host (one DDS domain) used to
// share run id "default" and merge. Each launch now gets its own, recorded in config.yaml,
// and a run resumed in its folder keeps it.
TEST_F(LauncherTest, TwoDefaultLaunchesGetDifferentRunIdsAndAResumedRunKeepsItsId) {
  setenv("FAKE_LEARNER", "exit0-after:300", 1);
  setenv("FAKE_ACTOR", "exit0-after:300", 1);
  std::vector<std::string> ids;
  const fs::path first_dir = run_dir_;
  for (const char* name : {"a", "b", "a"}) {
    run_dir_ = root_ / name;
    ChildProcess launcher = StartLauncher({}, /*with_run_id=*/false);
    const auto exit = launcher.WaitFor(milliseconds(30000));
    ASSERT_TRUE(exit.has_value());
    ASSERT_EQ(exit->Describe(), "exit code 0") << ReadFile(root_ / "launcher.out");
    ids.push_back(config::RecordedRunId((run_dir_ / "config.yaml").string()));
    ASSERT_FALSE(ids.back().empty()) << ReadFile(run_dir_ / "config.yaml");
    EXPECT_NE(ids.back(), "auto");
  }
  EXPECT_NE(ids[0], ids[1]) << "two launches, one run id";
  EXPECT_EQ(ids[2], ids[0]) << "the resumed run changed its run id";
  run_dir_ = first_dir;
}

// Issue 39: two `srics run` with one run id (the config names it) started a second apart both
// finished with exit 0: the first run's nodes.csv listed the second run's processes and each
// learner refused the other's episodes. Now the second exits 2 before it starts a role or
// writes a file, naming the first launcher's host and pid and how to pick another run id, and
// the first runs on to its end without a trace of the second in its nodes.csv.
TEST_F(LauncherTest, ASecondLauncherWithTheSameRunIdExits2NamingTheFirstWhichRunsOnUndisturbed) {
  setenv("FAKE_LEARNER", "exit0-after:9000", 1);
  setenv("FAKE_ACTOR", "exit0-after:10000", 1);
  const fs::path first_dir = run_dir_;
  ChildProcess first =
      StartLauncher({}, true, std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml", "first.out");
  // the first is under way: its roles run
  const auto deadline = std::chrono::steady_clock::now() + milliseconds(20000);
  while (RolePids().size() < 4 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(milliseconds(50));
  ASSERT_EQ(RolePids().size(), 4u) << ReadFile(root_ / "first.out");
  const std::vector<pid_t> first_roles = RolePids();

  // the second: same run id, same domain, its own folder
  run_dir_ = root_ / "second";
  const auto start = std::chrono::steady_clock::now();
  ChildProcess second =
      StartLauncher({}, true, std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml", "second.out");
  const auto second_exit = second.WaitFor(milliseconds(20000));
  ASSERT_TRUE(second_exit.has_value());
  EXPECT_LT(std::chrono::steady_clock::now() - start, milliseconds(8000));
  const std::string said = ReadFile(root_ / "second.out");
  EXPECT_EQ(second_exit->Describe(), "exit code 2") << said;
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  EXPECT_THAT(said, HasSubstr("launcher-test-" + std::to_string(getpid())));
  EXPECT_THAT(said, HasSubstr(std::string(host) + ", pid " + std::to_string(first.pid())));
  EXPECT_THAT(said, HasSubstr("--set transport.run_id="));
  EXPECT_FALSE(fs::exists(run_dir_)) << "the second wrote into its run folder";
  run_dir_ = first_dir;

  // the first: on to its end, its roles never restarted, nothing of the second in its files
  const auto first_exit = first.WaitFor(milliseconds(60000));
  ASSERT_TRUE(first_exit.has_value());
  EXPECT_EQ(first_exit->Describe(), "exit code 0") << ReadFile(root_ / "first.out");
  EXPECT_EQ(RolePids(), first_roles) << "a role of the first run was restarted";
  const std::string nodes = ReadFile(run_dir_ / "nodes.csv");
  EXPECT_THAT(nodes, HasSubstr(",launcher,")) << "the launcher announces itself";
  EXPECT_THAT(nodes, HasSubstr("," + std::string(host) + "," + std::to_string(first.pid()) + ","));
  EXPECT_THAT(nodes, Not(HasSubstr("," + std::string(host) + "," + std::to_string(second.pid()) + ",")));
  EXPECT_THAT(ReadFile(run_dir_ / "logs/launcher.log"), HasSubstr("pid " + std::to_string(second.pid())))
      << "the first says that a second launcher came and was refused";
  EXPECT_THAT(ReadFile(root_ / "first.out"), HasSubstr("run finished: the budget is done; restarts 0"));
}

// Issue 39: 400 bytes of nested anchors grew srics run to 3.9 GB in 39 s (std::bad_alloc).
TEST_F(LauncherTest, AnAnchorBombConfigExitsWithCode2InUnderASecondNamingTheCause) {
  const std::string config = (root_ / "bomb.yaml").string();
  fs::copy_file(std::string(SRICS_SOURCE_DIR) + "/tests/fuzz/corpus/config/anchor-bomb.yaml", config);
  const auto start = std::chrono::steady_clock::now();
  ChildProcess launcher = StartLauncher({}, true, config);
  const auto exit = launcher.WaitFor(milliseconds(20000));
  ASSERT_TRUE(exit.has_value());
  EXPECT_LT(std::chrono::steady_clock::now() - start, milliseconds(1000));
  EXPECT_EQ(exit->Describe(), "exit code 2");
  EXPECT_THAT(ReadFile(root_ / "launcher.out"),
              HasSubstr(config + ":1: an anchor (&name): anchors and aliases are not accepted in a config"));
  EXPECT_FALSE(fs::exists(run_dir_));
}

// Issue 15: a non-scalar key gave yaml-cpp's "bad conversion" and exit code 1.
TEST_F(LauncherTest, ANonScalarKeyOrAZeroEvaluationPeriodExitsWithCode2NamingFileLineAndKey) {
  const std::string config = (root_ / "bad.yaml").string();
  std::ofstream(config) << "extends: " << SRICS_SOURCE_DIR << "/deploy/configs/rearrange-1-cpu.yaml\n"
                        << "transport:\n  [domain_id, run_id]: 5\n";
  ChildProcess launcher = StartLauncher({}, true, config);
  ASSERT_NO_FATAL_FAILURE(ExpectUsageExitSaying(
      launcher, config + ":3: transport: expected a plain key (a name such as 'domain_id'), got a list as a key"));

  ChildProcess zero = StartLauncher({"--set", "actors.eval_every_env_steps=0"});
  ExpectUsageExitSaying(zero, "command line: actors.eval_every_env_steps: expected a positive integer, got '0'");
}

// Issue 15: a role that hangs (here an actor stopped with SIGSTOP: alive for the kernel and
// for DDS liveliness, silent otherwise) used to stall the run forever. The real role programs:
// the launcher kills the silent actor after transport.stalled_node_restart_s, restarts it, and
// the run finishes.
TEST_F(LauncherTest, AHungActorIsKilledRestartedAndTheRunFinishes) {
  const std::string config = std::string(SRICS_SOURCE_DIR) + "/tests/integration/system-test.yaml";
  ChildProcess launcher = ChildProcess::Spawn(
      {SRICS_LAUNCHER, "run", config, "--run-dir", run_dir_.string(), "--display", "plain", "--stop-timeout", "5",
       "--set", "transport.domain_id=" + std::to_string(150 + getpid() % 50), "--set",
       "transport.run_id=hung-test-" + std::to_string(getpid()),
       // a sanitized role can be busy that long between its NodeStatus samples
       "--set", "transport.stalled_node_restart_s=" + std::to_string(8 * testing::kSanitizerSlowdown)},
      {.output_file = (root_ / "launcher.out").string(), .own_process_group = true, .parent_death_signal = SIGKILL});
  // actor 0's pid, once it is under way (its NodeStatus rows in nodes.csv)
  pid_t actor = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120 * testing::kSanitizerSlowdown);
  while (actor == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(milliseconds(200));
    const std::string log = fs::exists(run_dir_ / "logs/launcher.log") ? ReadFile(run_dir_ / "logs/launcher.log") : "";
    const size_t at = log.find("actor-0 started (pid ");
    if (at != std::string::npos && ReadFile(run_dir_ / "nodes.csv").find(",actor,0,") != std::string::npos)
      actor = std::atoi(log.c_str() + at + std::string("actor-0 started (pid ").size());
  }
  ASSERT_GT(actor, 0) << ReadFile(root_ / "launcher.out");
  ASSERT_EQ(kill(actor, SIGSTOP), 0);
  const auto exit = launcher.WaitFor(milliseconds(300000 * testing::kSanitizerSlowdown));
  ASSERT_TRUE(exit.has_value()) << ReadFile(root_ / "launcher.out");
  EXPECT_EQ(exit->Describe(), "exit code 0") << ReadFile(root_ / "launcher.out");
  const std::string log = ReadFile(run_dir_ / "logs/launcher.log");
  EXPECT_THAT(log, HasSubstr("actor-0 hung: no NodeStatus for"));
  EXPECT_THAT(log, HasSubstr("actor-0 ended: signal 9"));
  EXPECT_THAT(log, HasSubstr("actor-0 restarted"));
  EXPECT_THAT(log, HasSubstr("stopping: the budget is done"));
  EXPECT_FALSE(ProcessExists(actor));
}

// The fields of eval.csv's rows with policy version 0 (the passive baseline first).
std::vector<std::vector<std::string>> PassiveRows(const fs::path& eval_csv) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(eval_csv);
  std::string line;
  std::getline(in, line);  // header: wall_time,run_id,actor_id,policy_version,...
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream split(line);
    for (std::string field; std::getline(split, field, ',');) fields.push_back(field);
    if (fields.size() > 8 && fields[3] == "0") rows.push_back(fields);
  }
  return rows;
}

// Issue 39: without DDS Security, a participant that published an EvalResult for actor 0 at
// policy version 0 before the run's own passive evaluation became the run's baseline:
// summary.txt read "passive object distance 0.0000" and eval.csv's first v0 row was the
// forged one. The launcher now plays the passive baseline itself and refuses a v0 result that
// disagrees: the stranger's is counted and shown as refused, and the baseline in summary.txt
// and eval.csv is what the run's actor measured. The real role programs, a tiny run.
TEST_F(LauncherTest, AStrangersPassiveEvaluationIsRefusedAndTheRunsActorSetsTheBaseline) {
  const std::string run_id = "passive-test-" + std::to_string(getpid());
  const std::string domain = std::to_string(150 + getpid() % 50);
  const std::string config_file = std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml";
  // a run of a few seconds (sweep_testing.h's kTinyRun)
  const std::vector<std::string> sets = srics::testing::TinyRunSettings(
      {"run.total_env_steps=1500", "learner.checkpoint_every_updates=100", "actors.count=1",
       "actors.eval_every_env_steps=500", "transport.domain_id=" + domain, "transport.run_id=" + run_id});
  std::vector<std::string> argv = {SRICS_LAUNCHER, "run",   config_file,      "--run-dir", run_dir_.string(),
                                   "--display",    "plain", "--stop-timeout", "10"};
  for (const std::string& set : sets) argv.insert(argv.end(), {"--set", set});

  // the stranger: a participant of its own on the run's domain, with the run's id
  const config::Config config = config::LoadConfig(config_file, sets);
  transport::Participant stranger(config.transport);
  transport::Writer<rl::EvalReport> forger(stranger);
  ChildProcess launcher = ChildProcess::Spawn(
      argv,
      {.output_file = (root_ / "launcher.out").string(), .own_process_group = true, .parent_death_signal = SIGKILL});
  // the launcher's monitor reads evaluations before any role starts: the forgery is there
  // long before the actor's passive evaluation (after the graph and the first weights)
  ASSERT_TRUE(forger.WaitForReaders(1, std::chrono::seconds(30 * testing::kSanitizerSlowdown)))
      << ReadFile(root_ / "launcher.out");
  rl::EvalReport forged;
  forged.actor_id = 0;
  forged.policy_version = 0;
  forged.summary.episodes = 2;  // actors.eval_episodes of the run
  forged.summary.entity_distance = {0.0f, 0.0f};
  forged.summary.subgoal_success = {1.0f, 1.0f};
  forged.summary.success_rate = 1.0f;
  ASSERT_EQ(forger.Write(forged), transport::WriteResult::kSent);

  const auto exit = launcher.WaitFor(milliseconds(240000 * testing::kSanitizerSlowdown));
  ASSERT_TRUE(exit.has_value()) << ReadFile(root_ / "launcher.out");
  EXPECT_EQ(exit->Describe(), "exit code 0") << ReadFile(root_ / "launcher.out");

  // what the run's actor measured, from its log
  const std::string actor_log = ReadFile(run_dir_ / "logs/actor-0.out");
  const std::string marker = "evaluation (passive)";
  const size_t at = actor_log.find(marker);
  ASSERT_NE(at, std::string::npos) << actor_log;
  const size_t value_at = actor_log.find("avg_object_distance ", at);
  ASSERT_NE(value_at, std::string::npos) << actor_log;
  const double measured = std::stod(actor_log.substr(value_at + std::string("avg_object_distance ").size()));
  EXPECT_GT(measured, 0.05);

  // eval.csv: one passive row, the actor's
  const auto rows = PassiveRows(run_dir_ / "eval.csv");
  ASSERT_FALSE(rows.empty()) << ReadFile(run_dir_ / "eval.csv");
  EXPECT_EQ(rows.size(), 1u) << ReadFile(run_dir_ / "eval.csv");
  EXPECT_NEAR(std::stod(rows[0][8]), measured, 1e-4) << ReadFile(run_dir_ / "eval.csv");
  // summary.txt: the actor's baseline, and the stranger's shown as refused
  const std::string summary = ReadFile(run_dir_ / "summary.txt");
  char expected[64];
  std::snprintf(expected, sizeof expected, "passive   object distance %.4f", measured);
  EXPECT_THAT(summary, HasSubstr(expected)) << summary;
  EXPECT_THAT(summary, HasSubstr("(1 not this run's refused)")) << summary;
  // counted and logged by the launcher
  const std::string log = ReadFile(run_dir_ / "logs/launcher.log");
  EXPECT_THAT(log, HasSubstr("passive evaluation (policy v0) from actor 0 refused, not this run's: avg object "
                             "distance 0.0000"));
  EXPECT_THAT(log, HasSubstr("passive baseline played here to check the actors'"));
}

}  // namespace
}  // namespace srics::launcher
