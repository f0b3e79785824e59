#include "deploy/monitor/display.h"

#include <pty.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cstdio>
#include <sstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/deploy/monitor/test_states.h"

namespace srics::monitor {
namespace {

using std::chrono::milliseconds;
using testing::Eval;
using testing::Graph;
using ::testing::HasSubstr;
using testing::Node;
using ::testing::Not;

// The line of `text` that contains `needle` ("" if none).
std::string LineWith(const std::string& text, const std::string& needle) {
  size_t at = text.find(needle);
  if (at == std::string::npos) return "";
  const size_t begin = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
  const size_t end = text.find('\n', at);
  return text.substr(begin, end - begin);
}

class DisplayTest : public ::testing::Test {
 protected:
  DisplayTest() {
    state_.lost_after = milliseconds(3000);
    rl::LearnerReport stats;
    stats.updates = 123456;
    testing::SetTrainingSteps(&stats, 50000);
    stats.replay_size = 48000;
    stats.episodes_accepted = 2400;
    stats.episodes_rejected = 3;
    stats.policy_version = 42;
    stats.q_loss = 0.25f;
    stats.alpha = 0.05f;
    stats.updates_per_second = 80.5f;
    Apply(&state_, "r1", stats, t0_);
    Apply(&state_, "r1", Graph(), t0_);
    Apply(&state_, "r1", Eval(0, 0, 0.20f), t0_);
    Apply(&state_, "r1", Eval(30, 40000, 0.15f), t0_);
    Apply(&state_, "r1", Eval(42, 50000, 0.10f), t0_);
    Apply(&state_, "r1", Node("graph", 0, rl::NodePhase::kTraining), t0_ + milliseconds(4500));
    Apply(&state_, "r1", Node("learner", 0, rl::NodePhase::kTraining), t0_ + milliseconds(4000));
    Apply(&state_, "r1", Node("actor", 0, rl::NodePhase::kTraining), t0_ + milliseconds(4000));
    Apply(&state_, "r1", Node("actor", 1, rl::NodePhase::kStopping), t0_);
    Apply(&state_, "r1", Node("actor", 2, rl::NodePhase::kTraining), t0_);  // crashed: quiet, no goodbye
  }
  const Clock::time_point t0_{};
  const Clock::time_point now_ = t0_ + milliseconds(5000);
  MonitorState state_;
};

TEST_F(DisplayTest, EmptyStateSaysNothingArrived) {
  const std::string text = Render(MonitorState{}, now_, {});
  EXPECT_THAT(text, HasSubstr("nothing received yet"));
  EXPECT_THAT(text, HasSubstr("none seen yet"));
}

TEST_F(DisplayTest, ShowsProgressAgainstTheBudget) {
  RenderOptions options;
  options.total_env_steps = 100000;
  const std::string text = Render(state_, now_, options);
  EXPECT_THAT(LineWith(text, "run r1"), HasSubstr("env steps 50,000 / 100,000"));
  EXPECT_THAT(LineWith(text, "run r1"), HasSubstr("50%"));
}

TEST_F(DisplayTest, ShowsLearnerStats) {
  const std::string line = LineWith(Render(state_, now_, {}), "learner   updates");
  EXPECT_THAT(line, HasSubstr("123,456 (80.5/s)"));
  EXPECT_THAT(line, HasSubstr("2,400 ok / 3 bad"));
  EXPECT_THAT(line, HasSubstr("policy v42"));
  EXPECT_THAT(line, HasSubstr("(5.0s ago)"));
}

TEST_F(DisplayTest, ShowsGraphEdgesAndDepths) {
  const std::string text = Render(state_, now_, {});
  const std::string graph = LineWith(text, "graph     v3");
  EXPECT_THAT(graph, HasSubstr("3 entities, 2 edges (0->1 0.93, 1->2 0.71)"));
  EXPECT_THAT(graph, HasSubstr("threshold 0.50"));
  EXPECT_THAT(LineWith(text, "depth:"), HasSubstr("e0 0  e1 1  e2 -"));
}

TEST_F(DisplayTest, ShowsLatestEvaluationAgainstThePassivePolicy) {
  const std::string text = Render(state_, now_, {});
  EXPECT_THAT(LineWith(text, "eval      policy"), HasSubstr("v42 at 50,000 env steps"));
  EXPECT_THAT(LineWith(text, "eval      policy"), HasSubstr("object distance 0.1000"));
  EXPECT_THAT(LineWith(text, "subgoal success"), HasSubstr("e0 1.00  e1 0.80  e2 0.25"));
  // 0.10 vs passive 0.20: half the distance
  EXPECT_THAT(LineWith(text, "passive"), HasSubstr("object distance -50%"));
  // history lists both trained evaluations, oldest first
  const size_t first = text.find("v30");
  ASSERT_NE(first, std::string::npos);
  EXPECT_LT(first, text.rfind("v42"));
}

TEST_F(DisplayTest, ShowsPassiveResultsRefusedAsNotTheRuns) {
  state_.runs.begin()->second.passive_refused = 2;
  EXPECT_THAT(LineWith(Render(state_, now_, {}), "passive"), HasSubstr("(2 not this run's refused)"));
  MonitorState state;
  state.runs["r1"].passive_refused = 1;
  EXPECT_THAT(Render(state, t0_, {}), HasSubstr("no passive baseline yet (1 not this run's refused)"));
}

TEST_F(DisplayTest, WithoutEvaluationSaysSo) {
  MonitorState state;
  Apply(&state, "r1", Node("actor", 0, rl::NodePhase::kExploring), t0_);
  const std::string text = Render(state, t0_, {});
  EXPECT_THAT(text, HasSubstr("no evaluation of a trained policy yet; no passive baseline yet"));
  EXPECT_THAT(text, HasSubstr("graph     none yet"));
  EXPECT_THAT(text, HasSubstr("learner   no stats yet"));
}

TEST_F(DisplayTest, NodeHealthPerRow) {
  const std::string text = Render(state_, now_, {});
  EXPECT_THAT(text, HasSubstr("nodes     3 alive, 1 lost, 1 exited"));
  EXPECT_THAT(LineWith(text, "host-learner"), HasSubstr("alive"));
  // actor 2 went quiet while training: lost; actor 1 said stopping: exited
  EXPECT_THAT(LineWith(text, "1002"), HasSubstr("LOST"));
  EXPECT_THAT(LineWith(text, "1001"), HasSubstr("exited"));
  EXPECT_THAT(LineWith(text, "1001"), HasSubstr("stopping"));
  EXPECT_THAT(LineWith(text, "1002"), HasSubstr("00:01:01"));  // uptime
}

TEST_F(DisplayTest, RunFilterHidesOtherRuns) {
  Apply(&state_, "other-run", Node("actor", 9, rl::NodePhase::kTraining), now_);
  Apply(&state_, "other-run", Eval(1, 10, 0.3f), now_);
  RenderOptions only_r1;
  only_r1.run_id = "r1";
  const std::string filtered = Render(state_, now_, only_r1);
  EXPECT_THAT(filtered, Not(HasSubstr("other-run")));
  EXPECT_THAT(filtered, Not(HasSubstr("1009")));
  const std::string all = Render(state_, now_, {});
  EXPECT_THAT(all, HasSubstr("run other-run"));
  EXPECT_THAT(LineWith(all, "1009"), HasSubstr("other-run"));  // run column with several runs
}

TEST_F(DisplayTest, ShowsLauncherProcessesAndEvents) {
  RenderOptions options;
  options.elapsed_s = 3725;
  options.max_wall_minutes = 30;
  options.processes = {{"learner", 4242, "running", 0, ""},
                       {"actor-1", 0, "restarting in 2.0s", 3, "signal 9 (Killed)"}};
  options.events = {"[00:01:00] actor-1 ended: signal 9 (Killed); restart 3 in 2.0s"};
  const std::string text = Render(state_, now_, options);
  EXPECT_THAT(LineWith(text, "srics-monitor"), HasSubstr("elapsed 01:02:05 / 00:30:00"));
  EXPECT_THAT(LineWith(text, "actor-1 "), HasSubstr("restarting in 2.0s"));
  EXPECT_THAT(LineWith(text, "actor-1 "), HasSubstr("signal 9 (Killed)"));
  EXPECT_THAT(LineWith(text, "4242"), HasSubstr("running"));
  EXPECT_THAT(text, HasSubstr("events\n  [00:01:00] actor-1 ended"));
}

TEST_F(DisplayTest, OneLineSummary) {
  const std::string line = RenderOneLine(state_, now_, "r1", 100000);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_THAT(line, HasSubstr("steps 50,000/100,000"));
  EXPECT_THAT(line, HasSubstr("updates 123,456"));
  EXPECT_THAT(line, HasSubstr("eval v42 obj.dist 0.1000 (passive 0.2000)"));
  EXPECT_THAT(line, HasSubstr("graph v3 2 edges"));
  EXPECT_THAT(line, HasSubstr("nodes 3 alive, 2 gone"));
}

// Issue 38: for the first minutes of a default run the line read "graph -" ten times while the
// graph service collected explore episodes and trained the GNN; it now says so.
TEST_F(DisplayTest, BeforeTheFirstGraphTheLineShowsWhatTheGraphServiceIsDoing) {
  MonitorState state;
  state.lost_after = milliseconds(3000);
  rl::NodeStatus graph = Node("graph", 0, rl::NodePhase::kExploring);
  graph.report.detail = "collecting: 120/1000 episodes, 0 updates";
  Apply(&state, "r2", graph, t0_);
  EXPECT_THAT(RenderOneLine(state, t0_, "r2", 100000), HasSubstr("graph: collecting: 120/1000 episodes, 0 updates"));
  EXPECT_THAT(LineWith(Render(state, t0_, {}), "graph     "),
              HasSubstr("none yet; the graph service: collecting: 120/1000 episodes, 0 updates"));
  graph.report.detail = "training: 1000/1000 episodes, 400 updates, held-out 0.0123";
  Apply(&state, "r2", graph, t0_ + milliseconds(1000));
  EXPECT_THAT(RenderOneLine(state, t0_ + milliseconds(1000), "r2", 100000), HasSubstr("graph: training: 1000/1000"));
  // once a graph is published the line shows the graph, as before
  EXPECT_THAT(RenderOneLine(state_, now_, "r1", 100000), HasSubstr("graph v3 2 edges"));
}

TEST_F(DisplayTest, RateAndEtaFromTheLastMinuteOfLearnerStats) {
  RenderOptions options;
  options.total_env_steps = 100000;
  EXPECT_THAT(LineWith(Render(state_, now_, options), "run r1"), Not(HasSubstr("ETA")));  // one sample: no rate
  // samples at 0, 10, 100 and 120 s: each time the oldest ones beyond the 60 s window go (two
  // are always kept), so the rate is 7,000 / 90 s, then 6,000 / 20 s = 300/s
  rl::LearnerReport stats = *state_.runs["r1"].learner;
  testing::SetTrainingSteps(&stats, 53000);
  Apply(&state_, "r1", stats, t0_ + std::chrono::seconds(10));
  testing::SetTrainingSteps(&stats, 60000);
  Apply(&state_, "r1", stats, t0_ + std::chrono::seconds(100));
  EXPECT_NEAR(*EnvStepRate(state_.runs["r1"]), 7000.0 / 90.0, 1e-9);
  testing::SetTrainingSteps(&stats, 66000);
  Apply(&state_, "r1", stats, t0_ + std::chrono::seconds(120));
  ASSERT_EQ(state_.runs["r1"].step_history.size(), 2u);  // the window keeps 100 s and 120 s
  EXPECT_NEAR(*EnvStepRate(state_.runs["r1"]), 300.0, 1e-9);
  const std::string line = LineWith(Render(state_, now_, options), "run r1");
  EXPECT_THAT(line, HasSubstr("300/s  ETA 00:01:53")) << line;  // (100,000 - 66,000) / 300
  EXPECT_THAT(RenderOneLine(state_, now_, "r1", 100000), HasSubstr("300 steps/s  ETA 00:01:53"));
  // a learner that starts again from zero: the rate starts again too
  testing::SetTrainingSteps(&stats, 100);
  Apply(&state_, "r1", stats, t0_ + std::chrono::seconds(130));
  EXPECT_FALSE(EnvStepRate(state_.runs["r1"]));
}

TEST_F(DisplayTest, RenderingIsPure) { EXPECT_EQ(Render(state_, now_, {}), Render(state_, now_, {})); }

// Characters (UTF-8 code points) of the longest line.
size_t LongestLine(const std::string& text) {
  size_t longest = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    size_t n = 0;
    for (char c : line) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
    longest = std::max(longest, n);
  }
  return longest;
}

TEST_F(DisplayTest, LinesAreClippedToTheWidthWithAMark) {
  EXPECT_EQ(ClipLines("abcdef\nab\nabcd\n", 4), "abc~\nab\nabcd\n");
  EXPECT_EQ(ClipLines("abcdef", 0), "abcdef") << "width 0: no clipping";
  // multi-byte characters count as one column and are never cut in half
  EXPECT_EQ(ClipLines("\u00b1\u00b1\u00b1\u00b1\u00b1\n", 3), "\u00b1\u00b1~\n");
  RenderOptions options;
  options.title = "srics run  " + std::string(200, 'x');
  options.processes = {{"actor-0", 4242, "running", 3, "signal 9 (Killed), a very long description of the end"}};
  options.events = {std::string(150, 'e')};
  const std::string full = Render(state_, now_, options);
  ASSERT_GT(LongestLine(full), 100u);
  for (size_t width : {40, 80, 100}) {
    const std::string clipped = ClipLines(full, width);
    EXPECT_EQ(LongestLine(clipped), width);
    EXPECT_EQ(std::count(clipped.begin(), clipped.end(), '\n'), std::count(full.begin(), full.end(), '\n'));
  }
  const std::string line = RenderOneLine(state_, now_, "r1", 100000);
  EXPECT_EQ(ClipLines(line, 30), line.substr(0, 29) + "~");
}

TEST(OutputWidthTest, TerminalWidthThenColumnsAndNoClippingOutsideATerminal) {
  EXPECT_EQ(ChooseOutputWidth(true, 120, "80"), 120u) << "the terminal's own width first";
  EXPECT_EQ(ChooseOutputWidth(true, 0, "80"), 80u) << "COLUMNS when the terminal does not say";
  EXPECT_EQ(ChooseOutputWidth(true, 0, nullptr), 0u);
  EXPECT_EQ(ChooseOutputWidth(true, 0, "wide"), 0u);
  EXPECT_EQ(ChooseOutputWidth(false, 0, "80"), 0u) << "files and pipes are not clipped";
  EXPECT_EQ(ChooseOutputWidth(false, 120, "80"), 0u);

  // a real terminal (a pseudo-terminal 57 columns wide), a pipe
  int master = -1, slave = -1;
  winsize size{};
  size.ws_row = 24;
  size.ws_col = 57;
  ASSERT_EQ(openpty(&master, &slave, nullptr, nullptr, &size), 0);
  EXPECT_EQ(OutputWidth(slave), 57u);
  size.ws_col = 91;  // resized: asked again at every redraw
  ASSERT_EQ(ioctl(slave, TIOCSWINSZ, &size), 0);
  EXPECT_EQ(OutputWidth(slave), 91u);
  close(slave);
  close(master);
  int pipe_fds[2];
  ASSERT_EQ(pipe(pipe_fds), 0);
  EXPECT_EQ(OutputWidth(pipe_fds[1]), 0u);
  close(pipe_fds[0]);
  close(pipe_fds[1]);
}

}  // namespace
}  // namespace srics::monitor
