// One run id, one run (issue 39): what a launcher makes of the statuses it hears on its run id.
// The two-launcher run over DDS is LauncherTest.ASecondLauncherWithTheSameRunIdExits2...

#include "deploy/launcher/run_guard.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace srics::launcher {
namespace {

using ::testing::HasSubstr;

RoleShare Whole(int actors) {
  RoleShare share;
  for (int k = 0; k < actors; ++k) share.actor_ids.push_back(k);
  return share;
}

Incarnation Launcher(const std::string& host, int32_t pid, int64_t start_ms, RoleShare share) {
  return {.host = host, .pid = pid, .start_ms = start_ms, .share = std::move(share)};
}

rl::NodeStatus StatusOf(const Incarnation& incarnation) {
  rl::NodeStatus status;
  status.role = "launcher";
  status.node_id = static_cast<uint32_t>(incarnation.pid);
  status.host = incarnation.host;
  status.pid = incarnation.pid;
  status.report.detail = IncarnationDetail(incarnation);
  return status;
}

rl::NodeStatus Role(const std::string& role, uint32_t id, const std::string& host, int32_t pid) {
  rl::NodeStatus status;
  status.role = role;
  status.node_id = id;
  status.host = host;
  status.pid = pid;
  return status;
}

TEST(RunGuardTest, TheDetailSaysTheStartAndTheRolesAndReadsBack) {
  RoleShare share{.graph = false, .learner = true, .actor_ids = {5, 0, 1, 2, 3, 7, 8}, .whole_run = false};
  const Incarnation self = Launcher("h1", 4242, 1733400000123, share);
  EXPECT_EQ(IncarnationDetail(self), "incarnation since 1733400000123; roles learner actors:0-3,5,7-8");
  rl::NodeStatus status = StatusOf(self);
  status.report.detail += " | rejected: status.foreign=1";  // what StatusPublisher appends
  const auto back = IncarnationOf(status);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->host, "h1");
  EXPECT_EQ(back->pid, 4242);
  EXPECT_EQ(back->start_ms, 1733400000123);
  EXPECT_FALSE(back->share.graph);
  EXPECT_TRUE(back->share.learner);
  EXPECT_EQ(back->share.actor_ids, (std::vector<int>{0, 1, 2, 3, 5, 7, 8}));
  for (const char* bad : {"", "training", "incarnation since x; roles graph", "incarnation since 12; roles wizard",
                          "incarnation since 12; roles actors:3-1", "incarnation since 12 roles graph"}) {
    status.report.detail = bad;
    EXPECT_FALSE(IncarnationOf(status).has_value()) << bad;
  }
}

TEST(RunGuardTest, OfTwoLaunchersOfTheSameRolesTheOneThatCameLaterLeaves) {
  const Incarnation first = Launcher("h1", 100, 1000, Whole(2));
  const Incarnation second = Launcher("h1", 200, 2000, Whole(2));
  EXPECT_EQ(Judge(second, StatusOf(first), false).verdict, Verdict::kWasFirst);
  EXPECT_EQ(Judge(second, StatusOf(first), false).who, "launcher on host h1, pid 100");
  EXPECT_EQ(Judge(first, StatusOf(second), false).verdict, Verdict::kCameLater);
  EXPECT_EQ(Judge(first, StatusOf(second), true).verdict, Verdict::kCameLater);  // also while it runs
  // started in the same millisecond: host, then pid decide, the same way on both sides
  const Incarnation twin = Launcher("h1", 300, 1000, Whole(2));
  EXPECT_EQ(Judge(twin, StatusOf(first), false).verdict, Verdict::kWasFirst);
  EXPECT_EQ(Judge(first, StatusOf(twin), false).verdict, Verdict::kCameLater);
  // its own status is not in the way
  EXPECT_EQ(Judge(first, StatusOf(first), false).verdict, Verdict::kNotInTheWay);
  // a launcher status that does not say what it runs is taken as the whole run, there first
  rl::NodeStatus vague = StatusOf(second);
  vague.report.detail = "training";
  EXPECT_EQ(Judge(first, vague, false).verdict, Verdict::kWasFirst);
}

TEST(RunGuardTest, HostsOfOneRunWithDifferentRolesAreNotInEachOthersWay) {
  const RoleShare services{.graph = true, .learner = true, .actor_ids = {}, .whole_run = false};
  const RoleShare actors_2_5{.graph = false, .learner = false, .actor_ids = {2, 3, 4, 5}, .whole_run = false};
  const RoleShare actors_5_6{.graph = false, .learner = false, .actor_ids = {5, 6}, .whole_run = false};
  const Incarnation a = Launcher("h1", 100, 1000, services);
  const Incarnation b = Launcher("h2", 100, 2000, actors_2_5);
  EXPECT_EQ(Judge(b, StatusOf(a), false).verdict, Verdict::kNotInTheWay);
  EXPECT_EQ(Judge(a, StatusOf(b), false).verdict, Verdict::kNotInTheWay);
  // the same actor on two hosts is
  const Incarnation c = Launcher("h3", 100, 3000, actors_5_6);
  EXPECT_EQ(Judge(c, StatusOf(b), false).verdict, Verdict::kWasFirst);
  // a whole run overlaps every share
  const Incarnation whole = Launcher("h4", 100, 4000, Whole(2));
  EXPECT_EQ(Judge(whole, StatusOf(a), false).verdict, Verdict::kWasFirst);
  // more actor ranges than a detail holds: any actor
  RoleShare many;
  many.graph = many.learner = false;
  for (int k = 0; k < 400; k += 2) many.actor_ids.push_back(k);
  const Incarnation d = Launcher("h5", 100, 5000, many);
  EXPECT_THAT(IncarnationDetail(d), HasSubstr("actors:*"));
  EXPECT_LE(IncarnationDetail(d).size(), transport::kDetailMaxLength);
  EXPECT_EQ(Judge(c, StatusOf(d), false).verdict, Verdict::kCameLater);
  EXPECT_EQ(Judge(a, StatusOf(d), false).verdict, Verdict::kNotInTheWay);
}

TEST(RunGuardTest, ALiveRoleOfItsShareBeforeItStartedAnyIsAnotherRunsAfterwardsItsOwn) {
  const RoleShare share{.graph = false, .learner = true, .actor_ids = {0, 1}, .whole_run = false};
  const Incarnation self = Launcher("h1", 100, 1000, share);
  EXPECT_EQ(Judge(self, Role("learner", 0, "h2", 77), false).verdict, Verdict::kWasFirst);
  EXPECT_EQ(Judge(self, Role("learner", 0, "h2", 77), false).who, "learner on host h2, pid 77");
  EXPECT_EQ(Judge(self, Role("actor", 1, "h2", 78), false).who, "actor 1 on host h2, pid 78");
  EXPECT_EQ(Judge(self, Role("actor", 2, "h2", 79), false).verdict, Verdict::kNotInTheWay);  // not its actor
  EXPECT_EQ(Judge(self, Role("graph", 0, "h2", 80), false).verdict, Verdict::kNotInTheWay);  // not its role
  EXPECT_EQ(Judge(self, Role("monitor", 0, "h2", 81), false).verdict, Verdict::kNotInTheWay);
  // once its roles run, their statuses are its own (a restarted role has another pid)
  EXPECT_EQ(Judge(self, Role("learner", 0, "h1", 90), true).verdict, Verdict::kNotInTheWay);
}

TEST(RunGuardTest, TheMessageNamesTheRunTheOtherProcessAndHowToPickAnotherRunId) {
  const std::string text = SecondRunMessage("exp7", 42, {Verdict::kWasFirst, "launcher on host h1, pid 100"});
  EXPECT_THAT(text, HasSubstr("run id 'exp7'"));
  EXPECT_THAT(text, HasSubstr("domain 42"));
  EXPECT_THAT(text, HasSubstr("launcher on host h1, pid 100"));
  EXPECT_THAT(text, HasSubstr("--set transport.run_id="));
  EXPECT_THAT(text, HasSubstr("--run-dir"));
}

TEST(RunGuardTest, TheListeningWindowIsAFewStatusPeriodsBounded) {
  config::TransportConfig transport;
  transport.status_period_s = 1.0;
  EXPECT_EQ(ListenWindow(transport), std::chrono::milliseconds(2500));
  transport.status_period_s = 0.1;
  EXPECT_EQ(ListenWindow(transport), std::chrono::milliseconds(2000));
  transport.status_period_s = 60;
  EXPECT_EQ(ListenWindow(transport), std::chrono::milliseconds(10000));
}

}  // namespace
}  // namespace srics::launcher
