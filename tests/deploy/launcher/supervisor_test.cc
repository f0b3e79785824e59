#include "deploy/launcher/supervisor.h"

#include <errno.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "tests/common/files/test_files.h"

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using ::testing::HasSubstr;

// No child of this process is left, reaped or not (no zombies).
void ExpectNoChildren() {
  errno = 0;
  EXPECT_EQ(waitpid(-1, nullptr, WNOHANG), -1);
  EXPECT_EQ(errno, ECHILD);
}

bool ProcessExists(pid_t pid) { return kill(pid, 0) == 0 || errno != ESRCH; }

int CountStarts(const std::string& output_file) {
  std::ifstream in(output_file);
  int starts = 0;
  for (std::string line; std::getline(in, line);) starts += line.rfind("start ", 0) == 0;
  return starts;
}

class SupervisorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    options_.on_event = [this](const std::string& e) { events_.push_back(e); };
  }
  void TearDown() override { ExpectNoChildren(); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  ChildSpec Spec(const std::string& name, std::vector<std::string> mode) const {
    std::vector<std::string> argv = {FAKE_CHILD};
    argv.insert(argv.end(), mode.begin(), mode.end());
    return {.name = name, .argv = argv, .output_file = Path(name + ".out")};
  }
  // Ticks until `done` holds or the timeout passes.
  template <typename Predicate>
  bool TickUntil(Supervisor* supervisor, Predicate done, milliseconds timeout = milliseconds(10000)) {
    const auto deadline = SteadyClock::now() + timeout;
    while (SteadyClock::now() < deadline) {
      for (size_t k : supervisor->Tick()) ended_.push_back(k);
      if (done()) return true;
      std::this_thread::sleep_for(milliseconds(5));
    }
    return false;
  }
  bool AnyEventHas(const std::string& text) const {
    for (const std::string& e : events_)
      if (e.find(text) != std::string::npos) return true;
    return false;
  }

  files::testing::ScratchFolder dir_{"srics_supervisor_test"};
  SupervisorOptions options_;
  std::vector<std::string> events_;
  std::vector<size_t> ended_;  // what Tick reported as ended for good, in order
};

TEST(BackoffTest, DoublesUpToTheCap) {
  BackoffPolicy policy{.initial = milliseconds(500), .factor = 2.0, .max = milliseconds(3000)};
  EXPECT_EQ(Supervisor::BackoffDelay(policy, 1), milliseconds(500));
  EXPECT_EQ(Supervisor::BackoffDelay(policy, 2), milliseconds(1000));
  EXPECT_EQ(Supervisor::BackoffDelay(policy, 3), milliseconds(2000));
  EXPECT_EQ(Supervisor::BackoffDelay(policy, 4), milliseconds(3000));
  EXPECT_EQ(Supervisor::BackoffDelay(policy, 1000), milliseconds(3000));
}

TEST_F(SupervisorTest, ChildCrashingOnceIsRestartedAfterTheBackoff) {
  options_.backoff.initial = milliseconds(400);
  Supervisor supervisor(options_);
  const size_t i = supervisor.Add(Spec("actor-0", {"crash-once", Path("marker"), "3"}));
  supervisor.StartAll();
  const pid_t first_pid = supervisor.status(i).pid;
  ASSERT_GT(first_pid, 0);

  ASSERT_TRUE(TickUntil(&supervisor, [&] { return supervisor.status(i).phase == ChildPhase::kWaitingToRestart; }));
  const auto crashed_at = SteadyClock::now();
  EXPECT_EQ(supervisor.status(i).last_exit->Describe(), "exit code 3");
  ASSERT_TRUE(TickUntil(&supervisor, [&] { return supervisor.status(i).phase == ChildPhase::kRunning; }));
  const auto waited = SteadyClock::now() - crashed_at;
  EXPECT_GE(waited, milliseconds(350));  // the backoff was respected (minus the detection slack)
  EXPECT_LT(waited, milliseconds(3000));
  EXPECT_EQ(supervisor.status(i).restarts, 1u);
  EXPECT_EQ(supervisor.total_restarts(), 1u);
  EXPECT_NE(supervisor.status(i).pid, first_pid);
  EXPECT_TRUE(AnyEventHas("actor-0 ended: exit code 3; restart 1 in 0.4s"));
  EXPECT_TRUE(AnyEventHas("actor-0 restarted"));

  // the second incarnation keeps running: no more restarts. Its start line comes after it
  // installed its SIGINT handler: wait for it (on a loaded machine, e.g. under the sanitizers
  // beside a learning run, a fixed 300 ms was not always enough, and StopAll then killed a
  // child that could not yet handle SIGINT)
  ASSERT_TRUE(TickUntil(&supervisor, [&] { return CountStarts(Path("actor-0.out")) == 2; }));
  std::this_thread::sleep_for(milliseconds(300));
  supervisor.Tick();
  EXPECT_EQ(supervisor.status(i).phase, ChildPhase::kRunning);
  EXPECT_EQ(supervisor.status(i).restarts, 1u);

  const pid_t pid = supervisor.status(i).pid;
  EXPECT_TRUE(supervisor.StopAll());
  EXPECT_EQ(supervisor.status(i).phase, ChildPhase::kFinished);
  EXPECT_TRUE(supervisor.status(i).last_exit->success());  // it handled SIGINT and exited 0
  EXPECT_FALSE(ProcessExists(pid));
}

TEST_F(SupervisorTest, ChildKilledBySignalIsRestarted) {
  options_.backoff.initial = milliseconds(50);
  Supervisor supervisor(options_);
  const size_t i = supervisor.Add(Spec("actor-1", {"crash-once", Path("marker"), "kill"}));
  supervisor.StartAll();
  ASSERT_TRUE(TickUntil(&supervisor, [&] {
    return supervisor.status(i).restarts == 1 && supervisor.status(i).phase == ChildPhase::kRunning;
  }));
  ASSERT_TRUE(supervisor.status(i).last_exit.has_value());
  EXPECT_TRUE(supervisor.status(i).last_exit->signaled);
  EXPECT_EQ(supervisor.status(i).last_exit->code, SIGKILL);
  EXPECT_TRUE(supervisor.StopAll());
}

TEST_F(SupervisorTest, BackoffGrowsAndTheSupervisorGivesUpAtTheLimit) {
  options_.backoff = {.initial = milliseconds(100), .factor = 2.0, .max = milliseconds(1000)};
  Supervisor supervisor(options_);
  ChildSpec spec = Spec("flaky", {"fail", "4"});
  spec.max_restarts = 2;
  const size_t i = supervisor.Add(spec);
  const auto start = SteadyClock::now();
  supervisor.StartAll();
  ASSERT_TRUE(TickUntil(&supervisor, [&] { return supervisor.status(i).phase == ChildPhase::kFailed; }));
  // three runs, waits of 100 ms then 200 ms between them
  EXPECT_GE(SteadyClock::now() - start, milliseconds(300));
  EXPECT_EQ(supervisor.status(i).restarts, 2u);
  EXPECT_EQ(CountStarts(Path("flaky.out")), 3);
  EXPECT_EQ(ended_, std::vector<size_t>{i});
  EXPECT_TRUE(AnyEventHas("restart 2 in 0.2s"));
  EXPECT_TRUE(AnyEventHas("gave up after 2 restarts"));
  EXPECT_TRUE(supervisor.AllDown());
}

TEST_F(SupervisorTest, ExitCodeZeroIsDoneNotRestarted) {
  Supervisor supervisor(options_);
  const size_t i = supervisor.Add(Spec("learner", {"exit0-after", "50"}));
  supervisor.StartAll();
  ASSERT_TRUE(TickUntil(&supervisor, [&] { return !ended_.empty(); }));
  EXPECT_EQ(ended_, std::vector<size_t>{i});
  EXPECT_EQ(supervisor.status(i).phase, ChildPhase::kFinished);
  EXPECT_EQ(supervisor.status(i).restarts, 0u);
}

TEST_F(SupervisorTest, NeverPolicyLeavesAFailedChildDown) {
  Supervisor supervisor(options_);
  ChildSpec spec = Spec("once", {"fail", "1"});
  spec.restart = RestartPolicy::kNever;
  const size_t i = supervisor.Add(spec);
  supervisor.StartAll();
  ASSERT_TRUE(TickUntil(&supervisor, [&] { return supervisor.status(i).phase == ChildPhase::kFailed; }));
  EXPECT_EQ(supervisor.status(i).restarts, 0u);
}

// Issue 15: a learner refusing its unusable checkpoints (or a bad config) was restarted five
// times before the run failed.
TEST_F(SupervisorTest, AFinalExitCodeIsNotRestarted) {
  Supervisor supervisor(options_);
  ChildSpec spec = Spec("learner", {"fail", "65"});
  spec.max_restarts = 5;
  spec.final_exit_codes = {2, 65};
  const size_t i = supervisor.Add(spec);
  ChildSpec other = Spec("graph", {"fail", "1"});
  other.max_restarts = 1;
  other.final_exit_codes = {2, 65};
  const size_t j = supervisor.Add(other);
  supervisor.StartAll();
  ASSERT_TRUE(TickUntil(&supervisor, [&] { return supervisor.status(i).phase == ChildPhase::kFailed; }));
  EXPECT_EQ(supervisor.status(i).restarts, 0u);
  ASSERT_TRUE(TickUntil(&supervisor, [&] { return supervisor.status(j).phase == ChildPhase::kFailed; }));
  EXPECT_EQ(supervisor.status(j).restarts, 1u) << "other codes are restarted as before";
}

TEST_F(SupervisorTest, StopAllStopsEveryChildWithOneSigintAndReapsThem) {
  options_.stop_timeout = milliseconds(5000);
  Supervisor supervisor(options_);
  std::vector<size_t> children;
  for (int k = 0; k < 4; ++k) children.push_back(supervisor.Add(Spec("actor-" + std::to_string(k), {"run"})));
  supervisor.StartAll();
  std::vector<pid_t> pids;
  for (size_t i : children) pids.push_back(supervisor.status(i).pid);
  std::this_thread::sleep_for(milliseconds(100));  // let them install their handlers

  const auto start = SteadyClock::now();
  EXPECT_TRUE(supervisor.StopAll());
  EXPECT_LT(SteadyClock::now() - start, milliseconds(1000));
  for (size_t i : children) {
    EXPECT_EQ(supervisor.status(i).phase, ChildPhase::kFinished);
    EXPECT_TRUE(supervisor.status(i).last_exit->success());
  }
  for (pid_t pid : pids) EXPECT_FALSE(ProcessExists(pid));
  EXPECT_TRUE(supervisor.AllDown());
}

TEST_F(SupervisorTest, ChildIgnoringSigintIsKilledAfterTheTimeout) {
  options_.stop_timeout = milliseconds(300);
  Supervisor supervisor(options_);
  const size_t stubborn = supervisor.Add(Spec("stubborn", {"stubborn"}));
  const size_t polite = supervisor.Add(Spec("polite", {"run"}));
  supervisor.StartAll();
  std::this_thread::sleep_for(milliseconds(100));
  const auto start = SteadyClock::now();
  EXPECT_FALSE(supervisor.StopAll());  // not clean: one needed SIGKILL
  const auto took = SteadyClock::now() - start;
  EXPECT_GE(took, milliseconds(300));
  EXPECT_LT(took, milliseconds(2000));
  EXPECT_EQ(supervisor.status(stubborn).phase, ChildPhase::kFailed);
  EXPECT_TRUE(supervisor.status(stubborn).last_exit->signaled);
  EXPECT_EQ(supervisor.status(stubborn).last_exit->code, SIGKILL);
  EXPECT_TRUE(supervisor.status(polite).last_exit->success());
  EXPECT_TRUE(AnyEventHas("stubborn did not stop within 0.3s: SIGKILL"));
}

TEST_F(SupervisorTest, StopAllCancelsAPendingRestart) {
  options_.backoff.initial = milliseconds(60000);
  Supervisor supervisor(options_);
  const size_t i = supervisor.Add(Spec("actor-0", {"fail", "2"}));
  supervisor.StartAll();
  ASSERT_TRUE(TickUntil(&supervisor, [&] { return supervisor.status(i).phase == ChildPhase::kWaitingToRestart; }));
  EXPECT_TRUE(supervisor.StopAll());
  EXPECT_EQ(supervisor.status(i).phase, ChildPhase::kFinished);
  EXPECT_TRUE(supervisor.AllDown());
}

TEST_F(SupervisorTest, MissingProgramFailsAtStartAndLeavesNothingRunning) {
  Supervisor supervisor(options_);
  const size_t ok = supervisor.Add(Spec("first", {"run"}));
  supervisor.Add({.name = "missing", .argv = {Path("no-such-program")}, .output_file = ""});
  try {
    supervisor.StartAll();
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot start missing: cannot execute"));
    EXPECT_THAT(e.what(), HasSubstr("No such file"));
  }
  EXPECT_NE(supervisor.status(ok).phase, ChildPhase::kRunning);
  EXPECT_TRUE(supervisor.AllDown());
}

TEST_F(SupervisorTest, DuplicateNamesAndEmptyArgvAreRejected) {
  Supervisor supervisor(options_);
  supervisor.Add(Spec("a", {"run"}));
  EXPECT_THROW(supervisor.Add(Spec("a", {"run"})), std::invalid_argument);
  ChildSpec empty;
  empty.name = "b";
  EXPECT_THROW(supervisor.Add(empty), std::invalid_argument);
}

TEST_F(SupervisorTest, DestructorStopsRunningChildren) {
  pid_t pid = 0;
  {
    Supervisor supervisor(options_);
    const size_t i = supervisor.Add(Spec("a", {"run"}));
    supervisor.StartAll();
    pid = supervisor.status(i).pid;
  }
  EXPECT_FALSE(ProcessExists(pid));
}

TEST_F(SupervisorTest, ChildProcessDestructorKillsAndReaps) {
  pid_t pid = 0;
  {
    ChildProcess child = ChildProcess::Spawn({FAKE_CHILD, "stubborn"});
    pid = child.pid();
    EXPECT_TRUE(child.running());
    EXPECT_FALSE(child.Poll().has_value());
  }
  EXPECT_FALSE(ProcessExists(pid));
}

TEST_F(SupervisorTest, ChildOutputGoesToItsFile) {
  ChildProcess child = ChildProcess::Spawn({FAKE_CHILD, "fail", "0"}, {.output_file = Path("out.txt")});
  ASSERT_TRUE(child.WaitFor(milliseconds(5000)).has_value());
  EXPECT_TRUE(child.exit_status()->success());
  EXPECT_EQ(CountStarts(Path("out.txt")), 1);
}

TEST_F(SupervisorTest, ChildrenHaveTheirOwnProcessGroup) {
  ChildProcess child = ChildProcess::Spawn({FAKE_CHILD, "run"});
  std::this_thread::sleep_for(milliseconds(50));
  EXPECT_EQ(getpgid(child.pid()), child.pid());  // a terminal's Ctrl-C does not reach it directly
  EXPECT_NE(getpgid(child.pid()), getpgid(0));
  child.Signal(SIGINT);
  ASSERT_TRUE(child.WaitFor(milliseconds(5000)).has_value());
  EXPECT_TRUE(child.exit_status()->success());
}

}  // namespace
}  // namespace srics::launcher
