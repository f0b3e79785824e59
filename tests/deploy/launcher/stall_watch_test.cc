// The hung-process watch: silence of a running child's NodeStatus, counted per incarnation.

#include "deploy/launcher/stall_watch.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <thread>

namespace srics::launcher {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using ::testing::HasSubstr;

class StallWatchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    actor_ = supervisor_.Add({.name = "actor-0", .argv = {"/bin/sleep", "30"}});
    learner_ = supervisor_.Add({.name = "learner", .argv = {"/bin/sleep", "30"}});
    supervisor_.StartAll();
    start_ = supervisor_.status(actor_).started_at;
  }
  // a NodeStatus of `pid` as the monitor would hold it, last seen at `when`
  void Heard(const std::string& role, int pid, monitor::Clock::time_point when) {
    monitor::NodeEntry& entry = state_.nodes[monitor::NodeKey{"run", role, 0}];
    entry.status.pid = pid;
    entry.last_seen = when;
  }
  std::vector<WatchedNode> Nodes() const { return {{actor_, "actor", 0}, {learner_, "learner", 0}}; }

  Supervisor supervisor_;
  size_t actor_ = 0, learner_ = 0;
  monitor::MonitorState state_;
  monitor::Clock::time_point start_;
};

TEST_F(StallWatchTest, ASilentRunningChildIsReportedOncePerIncarnation) {
  StallWatch watch(seconds(5), "run", Nodes());
  Heard("actor", supervisor_.status(actor_).pid, start_ + seconds(3));
  Heard("learner", supervisor_.status(learner_).pid, start_ + seconds(3));
  EXPECT_TRUE(watch.Check(supervisor_, state_, start_ + seconds(7)).empty()) << "4 s of silence is not 5";
  Heard("learner", supervisor_.status(learner_).pid, start_ + seconds(8));  // the learner goes on
  const auto hung = watch.Check(supervisor_, state_, start_ + seconds(9));
  ASSERT_EQ(hung.size(), 1u);
  EXPECT_EQ(hung[0].first, actor_);
  EXPECT_THAT(hung[0].second, HasSubstr("no NodeStatus for 6 s while its process runs"));
  EXPECT_TRUE(watch.Check(supervisor_, state_, start_ + seconds(20)).size() == 1u) << "only the learner now";
  EXPECT_TRUE(watch.Check(supervisor_, state_, start_ + seconds(30)).empty()) << "each reported once";
}

TEST_F(StallWatchTest, AStatusOfAnEarlierProcessDoesNotCountAndSilenceCountsFromTheStart) {
  StallWatch watch(seconds(5), "run", Nodes());
  Heard("actor", supervisor_.status(actor_).pid + 100000, start_ + seconds(9));  // another incarnation's
  Heard("learner", supervisor_.status(learner_).pid, start_ + seconds(9));
  const auto hung = watch.Check(supervisor_, state_, start_ + seconds(6));
  ASSERT_EQ(hung.size(), 1u);
  EXPECT_EQ(hung[0].first, actor_);
  EXPECT_THAT(hung[0].second, HasSubstr("no NodeStatus since its start 6 s"));
}

TEST_F(StallWatchTest, ZeroMeansNeverAndStoppedChildrenAreNotWatched) {
  StallWatch never(seconds(0), "run", Nodes());
  EXPECT_TRUE(never.Check(supervisor_, state_, start_ + seconds(1000)).empty());
  supervisor_.StopAll();
  StallWatch watch(seconds(5), "run", Nodes());
  EXPECT_TRUE(watch.Check(supervisor_, state_, start_ + seconds(1000)).empty());
}

TEST_F(StallWatchTest, AKilledHungChildIsRestartedByTheSupervisor) {
  StallWatch watch(seconds(1), "run", Nodes());
  const int first_pid = supervisor_.status(actor_).pid;
  Heard("learner", supervisor_.status(learner_).pid, start_ + seconds(100));
  for (const auto& [child, why] : watch.Check(supervisor_, state_, start_ + seconds(2)))
    EXPECT_TRUE(supervisor_.Kill(child, why));
  const auto deadline = std::chrono::steady_clock::now() + seconds(10);
  while (supervisor_.status(actor_).restarts == 0 && std::chrono::steady_clock::now() < deadline) {
    supervisor_.Tick();
    std::this_thread::sleep_for(milliseconds(20));
  }
  EXPECT_EQ(supervisor_.status(actor_).restarts, 1u);
  EXPECT_NE(supervisor_.status(actor_).pid, first_pid);
  EXPECT_EQ(supervisor_.status(actor_).last_exit->Describe(), "signal 9 (Killed)");
}

}  // namespace
}  // namespace srics::launcher
