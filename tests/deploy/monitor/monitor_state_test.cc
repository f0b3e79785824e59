#include "deploy/monitor/monitor_state.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/deploy/monitor/test_states.h"

namespace srics::monitor {
namespace {

using std::chrono::milliseconds;
using testing::Eval;
using testing::Graph;
using testing::Node;
using testing::SetTrainingSteps;

TEST(MonitorStateTest, LostAfterIsLeasePlusTwoStatusPeriods) {
  config::TransportConfig transport;
  transport.liveliness_lease_s = 2.0;
  transport.status_period_s = 0.5;
  EXPECT_EQ(LostAfter(transport), milliseconds(3000));
}

TEST(MonitorStateTest, NodeStatusIsKeyedByRunRoleAndId) {
  MonitorState state;
  const Clock::time_point t0{};
  Apply(&state, "r1", Node("actor", 0, rl::NodePhase::kExploring), t0);
  Apply(&state, "r1", Node("actor", 0, rl::NodePhase::kTraining), t0 + milliseconds(100));
  Apply(&state, "r1", Node("actor", 1, rl::NodePhase::kTraining), t0);
  Apply(&state, "r2", Node("actor", 0, rl::NodePhase::kTraining), t0);
  ASSERT_EQ(state.nodes.size(), 3u);
  const NodeEntry& a0 = state.nodes.at({"r1", "actor", 0});
  EXPECT_EQ(a0.status.report.phase, rl::NodePhase::kTraining);
  EXPECT_EQ(a0.statuses, 2u);
  EXPECT_EQ(a0.first_seen, t0);
  EXPECT_EQ(a0.last_seen, t0 + milliseconds(100));
}

// Issue 15: peer strings were printed raw; a NodeStatus could clear the terminal or set its
// title. Every byte outside printable ASCII is now shown as '?'.
TEST(MonitorStateTest, PeerStringsAreKeptPrintable) {
  EXPECT_EQ(PrintableText("actor-1 on lab3, v2 (ok)"), "actor-1 on lab3, v2 (ok)");
  EXPECT_EQ(PrintableText("\x1b[2J\x1b]0;t\x07x\r\n\t\x7f"), "?[2J?]0;t?x????");
  EXPECT_EQ(PrintableText("\xc2\x9b"
                          "31m \xe2\x86\x92"),
            "??31m ???");  // C1 CSI in UTF-8, an arrow
  EXPECT_EQ(PrintableText(std::string("a\0b", 3)), "a?b");

  MonitorState state;
  rl::NodeStatus status = Node("actor\x1b[31m", 0, rl::NodePhase::kTraining);
  status.host = "h\r";
  status.report.detail = "\x1b[H";
  Apply(&state,
        "r\x1b"
        "1",
        status, Clock::time_point{});
  ASSERT_EQ(state.nodes.size(), 1u);
  const auto& [key, node] = *state.nodes.begin();
  EXPECT_EQ(key.run_id, "r?1");
  EXPECT_EQ(key.role, "actor?[31m");
  EXPECT_EQ(node.status.host, "h?");
  EXPECT_EQ(node.status.report.detail, "?[H");
}

// Node health over time: a node is lost 1000 ms after its last status; times are ms after t0.
class NodeHealthTest : public ::testing::Test {
 protected:
  NodeHealthTest() { state.lost_after = milliseconds(1000); }
  // `role` `id` reports state `s` at `ms`.
  void Report(const std::string& role, uint32_t id, rl::NodePhase s, int ms) {
    Apply(&state, "r1", Node(role, id, s), At(ms));
  }
  Clock::time_point At(int ms) const { return t0 + milliseconds(ms); }
  const NodeEntry& Entry(const std::string& role, uint32_t id) const { return state.nodes.at({"r1", role, id}); }

  MonitorState state;
  const Clock::time_point t0{};
};

TEST_F(NodeHealthTest, QuietNodeIsLostUnlessItSaidStopping) {
  Report("actor", 0, rl::NodePhase::kTraining, 0);
  Report("learner", 0, rl::NodePhase::kStopping, 0);
  const NodeEntry& actor = Entry("actor", 0);
  const NodeEntry& learner = Entry("learner", 0);
  EXPECT_EQ(HealthOf(state, actor, At(1000)), NodeHealth::kAlive);
  EXPECT_EQ(HealthOf(state, actor, At(1001)), NodeHealth::kLost);
  EXPECT_EQ(HealthOf(state, learner, At(999)), NodeHealth::kAlive);
  EXPECT_EQ(HealthOf(state, learner, At(1500)), NodeHealth::kExited);
}

TEST_F(NodeHealthTest, QuietNodeWithLiveWritersIsBusyNotLost) {
  Report("graph", 0, rl::NodePhase::kTraining, 0);
  Report("actor", 0, rl::NodePhase::kTraining, 1500);
  Report("actor", 1, rl::NodePhase::kStopping, 0);  // said goodbye: its writer is gone
  const NodeEntry& graph = Entry("graph", 0);
  const Clock::time_point now = At(2000);
  state.liveliness_known = true;
  state.status_writers_alive = 2;  // graph and actor 0: the graph is only busy
  EXPECT_EQ(HealthOf(state, graph, now), NodeHealth::kQuiet);
  state.status_writers_alive = 1;  // one writer lost its liveliness: the quiet one is lost
  EXPECT_EQ(HealthOf(state, graph, now), NodeHealth::kLost);
  state.liveliness_known = false;  // without liveliness, quiet means lost
  state.status_writers_alive = 2;
  EXPECT_EQ(HealthOf(state, graph, now), NodeHealth::kLost);
}

TEST_F(NodeHealthTest, NewlyGoneReportsEachTransitionOnceAndForgetsNodesThatCameBack) {
  Report("actor", 0, rl::NodePhase::kTraining, 0);
  Report("actor", 1, rl::NodePhase::kTraining, 1500);
  std::map<NodeKey, NodeHealth> gone;
  std::vector<NodeKey> first = NewlyGone(state, At(2000), &gone);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].node_id, 0u);
  EXPECT_TRUE(NewlyGone(state, At(2100), &gone).empty());
  // actor 0 restarts and reports again: alive, forgotten; it may be reported again later
  Report("actor", 0, rl::NodePhase::kExploring, 2200);
  EXPECT_TRUE(NewlyGone(state, At(2300), &gone).empty());
  EXPECT_TRUE(gone.empty());
  // later both went quiet: actor 0 is reported a second time, actor 1 for the first time
  EXPECT_EQ(NewlyGone(state, At(3300), &gone).size(), 2u);
  EXPECT_EQ(gone.size(), 2u);
}

TEST(MonitorStateTest, PassiveBaselineIsTheFirstVersionZeroEvaluation) {
  MonitorState state;
  Apply(&state, "r1", Eval(0, 0, 0.20f), {});
  Apply(&state, "r1", Eval(0, 0, 0.30f), {});  // another evaluator's passive run: not the baseline
  Apply(&state, "r1", Eval(5, 5000, 0.15f), {});
  Apply(&state, "r1", Eval(9, 10000, 0.10f), {});
  const RunView& run = state.runs.at("r1");
  ASSERT_TRUE(run.passive.has_value());
  EXPECT_FLOAT_EQ(run.passive->summary.avg_object_distance, 0.20f);
  ASSERT_EQ(run.evals.size(), 2u);
  EXPECT_EQ(LatestEval(run)->policy_version, 9u);
  EXPECT_EQ(EnvSteps(run), 10000u);
}

// Issue 39: a recorder that played the run's passive baseline itself refuses a v0 result that
// is not it (a stranger's object distance 0), and takes the actor's, whose float fields round
// the played figures.
TEST(MonitorStateTest, PassiveMismatchRefusesWhatIsNotTheRunsPassiveEvaluation) {
  rl::EvaluationSummary played;
  played.episodes = 20;
  played.avg_distance = 0.1301 + 0.01;
  played.avg_object_distance = 0.1301;
  played.success_rate = 0.5;
  played.entity_distance = {0.01, 0.1, 0.2};
  const rl::EvalReport actor = Eval(0, 0, 0.1301f);
  EXPECT_EQ(PassiveMismatch(actor, played), "") << "float rounding of the wire's fields";
  rl::EvalReport other_subgoals = actor;  // what depends on the actor's graph is not compared
  other_subgoals.summary.selectivity = 0.1f;
  other_subgoals.summary.subgoal_success = {0, 0, 0};
  other_subgoals.graph_version = 7;
  EXPECT_EQ(PassiveMismatch(other_subgoals, played), "");

  EXPECT_EQ(PassiveMismatch(Eval(0, 0, 0.0f), played),
            "avg object distance 0.0000, the run's passive evaluation gives 0.1301");
  rl::EvalReport forged = actor;
  forged.summary.episodes = 3;
  EXPECT_EQ(PassiveMismatch(forged, played), "3 episodes, the run's passive evaluation has 20");
  forged = actor;
  forged.summary.avg_distance = std::nanf("");
  EXPECT_EQ(PassiveMismatch(forged, played), "avg distance nan, the run's passive evaluation gives 0.1401");
  forged = actor;
  forged.summary.success_rate = 1;
  EXPECT_NE(PassiveMismatch(forged, played), "");
  forged = actor;
  forged.summary.entity_distance = {0.01f, 0.1f};
  EXPECT_EQ(PassiveMismatch(forged, played), "2 entity distances, the run has 3");
  forged = actor;
  forged.summary.entity_distance[2] = 0.2005f;  // 5e-4 m off: beyond the tolerance
  EXPECT_EQ(PassiveMismatch(forged, played), "entity 2 distance 0.2005, the run's passive evaluation gives 0.2000");
}

TEST(MonitorStateTest, EvaluationHistoryIsBounded) {
  MonitorState state;
  state.max_evals_kept = 3;
  for (uint64_t v = 1; v <= 10; ++v) Apply(&state, "r1", Eval(v, v * 100, 0.1f), {});
  const RunView& run = state.runs.at("r1");
  ASSERT_EQ(run.evals.size(), 3u);
  EXPECT_EQ(run.evals.front().policy_version, 8u);
  EXPECT_EQ(run.evals.back().policy_version, 10u);
}

TEST(MonitorStateTest, EnvStepsIsTheLargerOfLearnerAndEvaluation) {
  MonitorState state;
  EXPECT_EQ(EnvSteps(RunView{}), 0u);
  rl::LearnerReport stats;
  SetTrainingSteps(&stats, 7000);
  Apply(&state, "r1", stats, {});
  EXPECT_EQ(EnvSteps(state.runs.at("r1")), 7000u);
  Apply(&state, "r1", Eval(3, 5000, 0.1f), {});
  EXPECT_EQ(EnvSteps(state.runs.at("r1")), 7000u);
  Apply(&state, "r1", Eval(4, 9000, 0.1f), {});
  EXPECT_EQ(EnvSteps(state.runs.at("r1")), 9000u);
}

TEST(MonitorStateTest, LearnerHistoryKeepsEveryStatsAndStartsOverWithAFreshLearner) {
  MonitorState state;
  rl::LearnerReport stats;
  for (uint64_t k = 1; k <= 5; ++k) {
    stats.updates = 100 * k;
    stats.q_loss = static_cast<float>(k);
    SetTrainingSteps(&stats, 1000 * k);
    Apply(&state, "r1", stats, {});
  }
  const LearnerHistory& history = state.runs.at("r1").learner_history;
  ASSERT_EQ(history.points.size(), 5u);
  EXPECT_EQ(history.points[2].updates, 300u);
  EXPECT_EQ(history.points[2].env_steps, 3000u);
  EXPECT_EQ(history.points[4].q_loss, 5.0f);
  // a learner that started afresh (its count went back): the history starts over
  stats.updates = 10;
  SetTrainingSteps(&stats, 50);
  Apply(&state, "r1", stats, {});
  ASSERT_EQ(state.runs.at("r1").learner_history.points.size(), 1u);
  EXPECT_EQ(state.runs.at("r1").learner_history.points[0].updates, 10u);
}

TEST(MonitorStateTest, WeightsKeepVersionAndSizeOnly) {
  MonitorState state;
  rl::WeightsUpdate weights;
  weights.version = 12;
  weights.update_count = 600;
  weights.architecture = "sac-attention";
  weights.parameters.assign(1000, 0.5f);
  Apply(&state, "r1", weights, {});
  const WeightsInfo& info = *state.runs.at("r1").weights;
  EXPECT_EQ(info.version, 12u);
  EXPECT_EQ(info.update_count, 600u);
  EXPECT_EQ(info.num_parameters, 1000u);
  EXPECT_EQ(info.architecture, "sac-attention");
}

TEST(MonitorStateTest, EdgeCountIgnoresTheDiagonalAndShortAdjacency) {
  EXPECT_EQ(EdgeCount(Graph()), 2u);
  rl::GraphUpdate truncated = Graph();
  truncated.graph.adjacency.resize(2);  // malformed: must not read past the end
  EXPECT_EQ(EdgeCount(truncated), 1u);
}

// Issue 39: every table keyed by something from the wire is bounded. A flood of 100,000
// invented node ids and run ids keeps the tables at their limits, counts what went, and keeps
// the nodes that report regularly and the monitor's own run.
TEST(MonitorBoundsTest, AFloodOfInventedIdsKeepsTheTablesAtTheirLimitsAndTheRealNodes) {
  MonitorState state;
  state.max_nodes = 64;
  state.max_runs = 8;
  state.own_run_id = "r1";
  const Clock::time_point t0{};
  // the run's real nodes, heard from a few times
  for (int k = 0; k < 3; ++k)
    for (const char* role : {"learner", "graph"})
      Apply(&state, "r1", testing::Node(role, 0, rl::NodePhase::kTraining), t0 + std::chrono::seconds(k));
  rl::EvalReport own = testing::Eval(0, 0, 0.2f);
  Apply(&state, "r1", own, t0);
  for (uint32_t i = 0; i < 100000; ++i) {
    Apply(&state, "r1", testing::Node("actor", 1000 + i, rl::NodePhase::kTraining), t0 + std::chrono::seconds(10));
    rl::EvalReport foreign = testing::Eval(3, 1000, 0.1f);
    Apply(&state, "flood-" + std::to_string(i), foreign, t0 + std::chrono::seconds(10));
  }
  EXPECT_EQ(state.nodes.size(), 64u);
  EXPECT_EQ(state.evicted_nodes, 100000u + 2u - 64u);
  EXPECT_EQ(state.runs.size(), 8u);
  EXPECT_EQ(state.evicted_runs, 100000u + 1u - 8u);
  EXPECT_TRUE(state.nodes.count({"r1", "learner", 0})) << "a node heard from regularly was forgotten";
  EXPECT_TRUE(state.nodes.count({"r1", "graph", 0}));
  ASSERT_TRUE(state.runs.count("r1")) << "the monitor's own run was forgotten";
  EXPECT_TRUE(state.runs.at("r1").passive.has_value());
}

}  // namespace
}  // namespace srics::monitor
