#include "learner/hac.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/links/in_memory_bus.h"
#include "common/rl/agent_shape.h"
#include "learner/acting_policy.h"
#include "learner/learner.h"
#include "learner/learner_loop.h"
#include "tests/learner/learner_testing.h"

namespace srics::learner {
namespace {

using ::testing::ElementsAre;
using ::testing::ElementsAreArray;
using ::testing::FloatNear;
using ::testing::Pointwise;

// A hand-made HAC episode: the arm (kind 0) and a puck (kind 1), T = 4, H = 3, two attempts:
//   step   arm          puck
//   0      (0.0, 0.5)   (0.1, 0.6)
//   1      (0.1, 0.5)   (0.1, 0.6)
//   2      (0.2, 0.5)   (0.1, 0.6)   attempt 0 [0, 2): subgoal (0.22, 0.5 | 0.1, 0.6), reached at 2
//   3      (0.2, 0.6)   (0.1, 0.6)
//   4      (0.1, 0.6)   (0.0, 0.6)   attempt 1 [2, 4): test subgoal (-0.1, 0.7 | 0.0, 0.45), missed
// full goal (0.0, 0.4 | -0.1, 0.7), never reached.
rl::Episode HandEpisode() {
  rl::Episode e;
  e.layout = {2, 2, false};
  e.entity_kinds = {0, 1};
  e.num_steps = 4;
  e.action_dim = 2;
  const float xy[5][4] = {{0.0f, 0.5f, 0.1f, 0.6f},
                          {0.1f, 0.5f, 0.1f, 0.6f},
                          {0.2f, 0.5f, 0.1f, 0.6f},
                          {0.2f, 0.6f, 0.1f, 0.6f},
                          {0.1f, 0.6f, 0.0f, 0.6f}};
  for (const auto& s : xy) e.states.insert(e.states.end(), {1, 0, s[0], s[1], 0, 1, s[2], s[3]});
  e.actions = {1, 0, 1, 0, 0, 1, -1, 0};
  e.mode = rl::EpisodeMode::kTrain;
  e.goal = {0.0f, 0.4f, -0.1f, 0.7f};
  e.subgoal_starts = {0, 2};
  e.subgoals = {0.22f, 0.5f, 0.1f, 0.6f, -0.1f, 0.7f, 0.0f, 0.45f};
  e.subgoal_tests = {0, 1};
  return e;
}

HacOptions HandOptions(int hindsight_goals) {
  HacOptions o;
  o.horizon = 3;
  o.threshold = 0.05;
  o.hindsight_goals = hindsight_goals;
  o.box = {-0.25f, 0.25f, 0.35f, 0.76f};  // centre (0, 0.555), half sizes (0.25, 0.205)
  return o;
}

// The subgoal xy (2N) as a high-level action, by hand: ((x - 0) / 0.25, (y - 0.555) / 0.205).
std::vector<float> Action(std::initializer_list<float> subgoal) {
  std::vector<float> a;
  int i = 0;
  for (float v : subgoal) a.push_back(i++ % 2 == 0 ? v / 0.25f : (v - 0.555f) / 0.205f);
  return a;
}

void ExpectTransition(const HacTransition& t, int t0, int t1, const std::vector<float>& goal,
                      const std::vector<float>& action, float reward, bool terminal, HacRule rule) {
  SCOPED_TRACE("transition " + std::to_string(t0) + " -> " + std::to_string(t1));
  EXPECT_EQ(t.t0, t0);
  EXPECT_EQ(t.t1, t1);
  EXPECT_THAT(t.goal, Pointwise(FloatNear(1e-6f), goal));
  EXPECT_THAT(t.action, Pointwise(FloatNear(1e-5f), action));
  EXPECT_EQ(t.reward, reward);
  EXPECT_EQ(t.terminal, terminal);
  EXPECT_EQ(t.rule, rule);
}

TEST(HacTransitionsTest, LowLevelHindsightActionAndGoalTransitionsByHand) {
  const rl::Episode e = HandEpisode();
  std::mt19937_64 rng(1);
  const HacTransitions got = BuildHacTransitions(e, HandOptions(1), rng);  // one goal: the attempt's last state
  ASSERT_EQ(got.low.size(), 8u);
  const std::vector<float> g0 = {0.22f, 0.5f, 0.1f, 0.6f}, g1 = {-0.1f, 0.7f, 0.0f, 0.45f};
  const std::vector<float> reached0 = {0.2f, 0.5f, 0.1f, 0.6f}, reached1 = {0.1f, 0.6f, 0.0f, 0.6f};
  const auto A = HacRule::kHindsightAction;
  const auto G = HacRule::kHindsightGoal;
  // attempt 0 with its subgoal: the arm is 0.12 away after step 0, 0.02 (reached) after step 1
  ExpectTransition(got.low[0], 0, 1, g0, {1, 0}, -1, false, A);
  ExpectTransition(got.low[1], 1, 2, g0, {1, 0}, 0, true, A);
  // attempt 0 with the state it reached as goal
  ExpectTransition(got.low[2], 0, 1, reached0, {1, 0}, -1, false, G);
  ExpectTransition(got.low[3], 1, 2, reached0, {1, 0}, 0, true, G);
  // attempt 1: its subgoal is never reached; its last state is 0.1 from the state before
  ExpectTransition(got.low[4], 2, 3, g1, {0, 1}, -1, false, A);
  ExpectTransition(got.low[5], 3, 4, g1, {-1, 0}, -1, false, A);
  ExpectTransition(got.low[6], 2, 3, reached1, {0, 1}, -1, false, G);
  ExpectTransition(got.low[7], 3, 4, reached1, {-1, 0}, 0, true, G);
}

TEST(HacTransitionsTest, HighLevelHindsightActionGoalAndSubgoalTestTransitionsByHand) {
  const rl::Episode e = HandEpisode();
  std::mt19937_64 rng(1);
  const HacTransitions got = BuildHacTransitions(e, HandOptions(1), rng);
  ASSERT_EQ(got.high.size(), 5u);
  // attempt 0 reached its subgoal: the proposed subgoal is the hindsight action; attempt 1
  // missed it: the state it reached is
  const std::vector<float> a0 = Action({0.22f, 0.5f, 0.1f, 0.6f}), a1 = Action({0.1f, 0.6f, 0.0f, 0.6f});
  EXPECT_THAT(a0, Pointwise(FloatNear(1e-5f), {0.88f, -0.268293f, 0.4f, 0.219512f}));
  const std::vector<float> goal = e.goal, reached1 = {0.1f, 0.6f, 0.0f, 0.6f};
  ExpectTransition(got.high[0], 0, 2, goal, a0, -1, false, HacRule::kHindsightAction);
  ExpectTransition(got.high[1], 2, 4, goal, a1, -1, false, HacRule::kHindsightAction);
  // attempt 1 was a missed test subgoal: its proposal costs -H = -3 and ends the episode
  ExpectTransition(got.high[2], 2, 4, goal, Action({-0.1f, 0.7f, 0.0f, 0.45f}), -3, true, HacRule::kSubgoalTest);
  // goal replay with the episode's last state: only attempt 1 reaches it
  ExpectTransition(got.high[3], 0, 2, reached1, a0, -1, false, HacRule::kHindsightGoal);
  ExpectTransition(got.high[4], 2, 4, reached1, a1, 0, true, HacRule::kHindsightGoal);
}

TEST(HacTransitionsTest, ATestSubgoalThatIsReachedIsNotPenalised) {
  rl::Episode e = HandEpisode();
  e.subgoal_tests = {1, 0};  // attempt 0 (reached) tested, attempt 1 (missed) not
  std::mt19937_64 rng(1);
  const HacTransitions got = BuildHacTransitions(e, HandOptions(1), rng);
  for (const HacTransition& t : got.high) EXPECT_NE(t.rule, HacRule::kSubgoalTest);
  EXPECT_EQ(got.high.size(), 4u);
}

TEST(HacTransitionsTest, HindsightGoalsAreStatesOfTheAttemptAndAlwaysItsLast) {
  const rl::Episode e = HandEpisode();
  for (uint64_t seed = 0; seed < 20; ++seed) {
    std::mt19937_64 rng(seed);
    const HacTransitions got = BuildHacTransitions(e, HandOptions(3), rng);
    // per attempt of 2 steps: 2 with the subgoal + min(3, 2 steps) goals x 2 steps
    ASSERT_EQ(got.low.size(), 2u * (2 + 4));
    bool last_used[2] = {false, false};
    for (const HacTransition& t : got.low) {
      if (t.rule != HacRule::kHindsightGoal) continue;
      const int attempt = t.t0 < 2 ? 0 : 1;
      // the goal is the xy of a state reached within the attempt (steps 1..2 or 3..4)
      bool found = false;
      for (int s = 2 * attempt + 1; s <= 2 * attempt + 2; ++s) {
        std::vector<float> xy(4);
        rl::AchievedGoal(e.layout, e.state(s), xy.data());
        if (xy == t.goal) found = true;
        if (xy == t.goal && s == 2 * attempt + 2) last_used[attempt] = true;
      }
      EXPECT_TRUE(found) << "seed " << seed;
      EXPECT_EQ(t.reward == 0, t.terminal);
    }
    EXPECT_TRUE(last_used[0] && last_used[1]) << "seed " << seed;
    // high level: 2 hindsight action + 1 test + min(3, 2 attempts) goals x 2 attempts
    EXPECT_EQ(got.high.size(), 2u + 1 + 2 * 2);
  }
}

TEST(HacTransitionsTest, ExplorationEpisodesGiveHindsightGoalTransitionsInChunksOfH) {
  rl::Episode e = HandEpisode();
  e.mode = rl::EpisodeMode::kExplore;
  e.goal.clear();
  e.subgoal_starts.clear();
  e.subgoals.clear();
  e.subgoal_tests.clear();
  std::mt19937_64 rng(1);
  const HacTransitions got = BuildHacTransitions(e, HandOptions(1), rng);
  // chunks [0, 3) and [3, 4), each replayed with its last state
  ASSERT_EQ(got.low.size(), 4u);
  for (const HacTransition& t : got.low) EXPECT_EQ(t.rule, HacRule::kHindsightGoal);
  EXPECT_THAT(got.low[0].goal, ElementsAre(0.2f, 0.6f, 0.1f, 0.6f));  // state 3
  EXPECT_TRUE(got.low[2].terminal);
  EXPECT_THAT(got.low[3].goal, ElementsAre(0.1f, 0.6f, 0.0f, 0.6f));  // state 4
  // no goal: only the goal replay of the high level, towards the last state
  ASSERT_EQ(got.high.size(), 2u);
  ExpectTransition(got.high[0], 0, 3, {0.1f, 0.6f, 0.0f, 0.6f}, Action({0.2f, 0.6f, 0.1f, 0.6f}), -1, false,
                   HacRule::kHindsightGoal);
  ExpectTransition(got.high[1], 3, 4, {0.1f, 0.6f, 0.0f, 0.6f}, Action({0.1f, 0.6f, 0.0f, 0.6f}), 0, true,
                   HacRule::kHindsightGoal);
}

TEST(TransitionReplayTest, BatchesCarryTheStoredTransitionPaddedAndMasked) {
  const rl::Episode e = HandEpisode();
  // room for 3 entities and goals/actions of 6: the episode's 2 entities are padded
  TransitionReplay replay(2, 3, 4, 6, 6);
  HacTransition t;
  t.t0 = 2;
  t.t1 = 4;
  t.goal = {1, 2, 3, 4};
  t.action = {0.5f, -0.5f, 0.25f, 0};
  t.reward = -3;
  t.terminal = true;
  replay.Add(e, t);
  TrainingBatch batch;
  std::mt19937_64 rng(3);
  replay.Sample(2, rng, &batch);
  ASSERT_EQ(batch.size, 2);
  for (int b = 0; b < 2; ++b) {
    const std::vector<float> state(batch.entities.begin() + b * 12, batch.entities.begin() + b * 12 + 8);
    EXPECT_EQ(state, std::vector<float>(e.state(2), e.state(2) + 8));
    EXPECT_EQ(batch.entities[b * 12 + 8], 0.0f);
    EXPECT_EQ(std::vector<float>(batch.next_entities.begin() + b * 12, batch.next_entities.begin() + b * 12 + 8),
              std::vector<float>(e.state(4), e.state(4) + 8));
    EXPECT_THAT(std::vector<float>(batch.mask.begin() + b * 3, batch.mask.begin() + b * 3 + 3), ElementsAre(1, 1, 0));
    EXPECT_THAT(std::vector<float>(batch.goal.begin() + b * 6, batch.goal.begin() + b * 6 + 6),
                ElementsAre(1, 2, 3, 4, 0, 0));
    EXPECT_THAT(std::vector<float>(batch.action.begin() + b * 6, batch.action.begin() + b * 6 + 6),
                ElementsAre(0.5f, -0.5f, 0.25f, 0, 0, 0));
    EXPECT_EQ(batch.reward[b], -3);
    EXPECT_EQ(batch.terminal[b], 1.0f);
  }
  // capacity 2: the oldest leaves
  t.reward = -1;
  t.terminal = false;
  replay.Add(e, t);
  replay.Add(e, t);
  EXPECT_EQ(replay.size(), 2u);
  replay.Sample(16, rng, &batch);
  for (float r : batch.reward) EXPECT_EQ(r, -1.0f);
}

// ------------------------------------------------------------------------- the learner

config::Config HacRun() {
  config::Config c = testing::SmallRun(config::Method::kHac);
  c.env.num_pucks = 1;
  c.agent.hac.horizon = 3;
  return c;
}

// HandEpisode in the layout of HacRun's environment (the same: arm and one puck).
TEST(HacLearnerTest, TrainsBothLevelsAndPublishesTheHighLevelThenTheLowLevel) {
  Learner learner(testing::OptionsOf(HacRun()));
  ASSERT_NE(learner.hac(), nullptr);
  for (int i = 0; i < 30; ++i) ASSERT_EQ(learner.Ingest(HandEpisode()), "");
  // per attempt of 2 steps: 2 with the subgoal + 2 goals x 2 steps; high: 2 + 1 test + 2 x 2
  EXPECT_EQ(learner.hac()->low_replay().size(), 30u * 12);
  EXPECT_EQ(learner.hac()->high_replay().size(), 30u * 7);
  ASSERT_TRUE(learner.CanUpdate());
  const std::vector<float> high_before = learner.hac()->high().PolicyWeights();
  const std::vector<float> low_before = learner.agent().PolicyWeights();
  for (int i = 0; i < 3; ++i) {
    const UpdateStats stats = learner.Update();
    EXPECT_TRUE(std::isfinite(stats.q_loss));
  }
  EXPECT_NE(learner.hac()->high().PolicyWeights(), high_before);
  EXPECT_NE(learner.agent().PolicyWeights(), low_before);
  std::vector<float> want = learner.hac()->high().PolicyWeights();
  const std::vector<float> low = learner.agent().PolicyWeights();
  want.insert(want.end(), low.begin(), low.end());
  EXPECT_EQ(learner.TakePolicyWeights(), want);
  EXPECT_EQ(learner.PolicySignature(),
            rl::HacPolicySignature(learner.hac()->high().policy(), learner.agent().policy()));
}

// LearnerStats carry the low level's losses and temperature; the learner's node status shows
// the high level's (a runaway high-level temperature froze a HAC learner once, and it could
// only be read from the checkpoint): "high level: Q loss ..., alpha ..., entropy ...", the
// figures of the high level's last update, its alpha that of the high agent.
TEST(HacLearnerTest, NodeStatusShowsTheHighLevelsLossAndTemperature) {
  struct Observer : links::BusObserver {
    void OnStatus(const std::string& role, uint32_t, const rl::NodeReport& report) override {
      if (role == "learner") detail = report.detail;
    }
    void OnLearnerStats(const rl::LearnerReport& report) override { low_q_loss = report.q_loss; }
    std::string detail;
    double low_q_loss = 0;
  } observer;
  links::InMemoryBus bus(&observer);
  auto link = bus.LearnerEnd();
  auto actor = bus.ActorEnd(0);
  config::Config c = HacRun();
  c.run.total_env_steps = 100000;
  LearnerLoopOptions options = LearnerLoopOptionsFor(c, rl::RunShapeFor(c), "");
  options.report_period_s = 0;
  LearnerLoop loop(options, link.get());
  loop.Step();
  EXPECT_THAT(observer.detail, ::testing::Not(::testing::HasSubstr("high level"))) << "no update yet";
  for (uint64_t id = 1; id <= 200 && loop.learner().counters().updates < 5; ++id) {
    rl::Episode e = HandEpisode();
    e.episode_id = id;
    ASSERT_TRUE(actor->PublishEpisode(e));
    loop.Step();
  }
  ASSERT_GE(loop.learner().counters().updates, 5u);
  loop.Step();
  const UpdateStats& high = loop.learner().hac()->last_high_update();
  EXPECT_GT(high.q_loss, 0);
  // the agent took one temperature step after the update measured it
  EXPECT_NEAR(high.alpha, loop.learner().hac()->high().alpha(), 1e-2 * high.alpha);
  double q_loss = 0, alpha = 0, entropy = 0;
  const size_t at = observer.detail.find("high level: ");
  ASSERT_NE(at, std::string::npos) << observer.detail;
  ASSERT_EQ(std::sscanf(observer.detail.c_str() + at, "high level: Q loss %lf, alpha %lf, entropy %lf", &q_loss, &alpha,
                        &entropy),
            3)
      << observer.detail;
  EXPECT_NEAR(q_loss, high.q_loss, 1e-3 * std::abs(high.q_loss));
  EXPECT_NEAR(alpha, high.alpha, 1e-3 * high.alpha);
  EXPECT_NEAR(entropy, high.entropy, 1e-3 * std::abs(high.entropy) + 1e-6);
  EXPECT_NE(q_loss, observer.low_q_loss) << "the low level's loss is the one in LearnerStats";
}

// HAC's Q bound, [-H, 0] on both levels unless agent.hac.bound_q is false; SAC's agents are
// unbounded.
TEST(HacLearnerTest, BothLevelsBoundTheirTargetsToMinusHToZero) {
  Learner hac(testing::OptionsOf(HacRun()));
  const std::pair<float, float> bound{-3.0f, 0.0f};
  EXPECT_EQ(hac.agent().target_bounds(), bound);
  EXPECT_EQ(hac.hac()->high().target_bounds(), bound);
  config::Config unbounded = HacRun();
  unbounded.agent.hac.bound_q = false;
  Learner plain_hac(LearnerOptionsFor(unbounded, rl::RunShapeFor(unbounded)));
  EXPECT_FALSE(plain_hac.agent().target_bounds());
  EXPECT_FALSE(plain_hac.hac()->high().target_bounds());
  Learner sac(testing::OptionsOf(testing::SmallRun(config::Method::kSacHer)));
  EXPECT_FALSE(sac.agent().target_bounds());
}

TEST(HacLearnerTest, RejectsHacEpisodesThatDoNotFitAndSubgoalsElsewhere) {
  Learner learner(testing::OptionsOf(HacRun()));
  rl::Episode no_subgoals = HandEpisode();
  no_subgoals.subgoal_starts.clear();
  no_subgoals.subgoals.clear();
  no_subgoals.subgoal_tests.clear();
  EXPECT_THAT(learner.Ingest(no_subgoals), ::testing::HasSubstr("need a full goal and the high level's subgoals"));
  rl::Episode too_long = HandEpisode();
  too_long.subgoal_starts = {0, 1};  // attempt 1 held 3 steps: allowed (H = 3)
  EXPECT_EQ(learner.Ingest(too_long), "");
  too_long.subgoal_starts = {0};  // one attempt of 4 steps
  too_long.subgoals.resize(4);
  too_long.subgoal_tests = {0};
  EXPECT_THAT(learner.Ingest(too_long), ::testing::HasSubstr("held 4 steps, this run allows 3"));
  EXPECT_EQ(learner.episodes_rejected(), 2u);
  // a learner of another method refuses subgoals
  config::Config sac_her = HacRun();
  sac_her.run.method = config::Method::kSacHer;
  Learner other(LearnerOptionsFor(sac_her, rl::RunShapeFor(sac_her)));
  EXPECT_THAT(other.Ingest(HandEpisode()), ::testing::HasSubstr("carry no subgoals"));
  EXPECT_EQ(other.episodes_rejected(), 1u);
}

TEST(HacLearnerTest, CheckpointHoldsBothLevels) {
  const std::string path = ::testing::TempDir() + "/hac_learner.srics";
  Learner learner(testing::OptionsOf(HacRun()));
  for (int i = 0; i < 30; ++i) ASSERT_EQ(learner.Ingest(HandEpisode()), "");
  for (int i = 0; i < 2; ++i) learner.Update();
  learner.SaveCheckpoint(path);
  Learner restored(testing::OptionsOf(HacRun()));
  EXPECT_NE(restored.TakePolicyWeights(), learner.TakePolicyWeights());
  restored.LoadCheckpoint(path);
  EXPECT_EQ(restored.hac()->high().PolicyWeights(), learner.hac()->high().PolicyWeights());
  EXPECT_EQ(restored.agent().PolicyWeights(), learner.agent().PolicyWeights());
  EXPECT_EQ(restored.counters().updates, 2u);
  // the replay keeps the subgoal records, and both levels' transitions are built again from it
  ASSERT_EQ(restored.replay().episodes(), 30u);
  EXPECT_EQ(restored.replay().contents().front(), learner.replay().contents().front());
  EXPECT_EQ(restored.replay().contents().front().subgoal_starts, HandEpisode().subgoal_starts);
  EXPECT_EQ(restored.hac()->low_replay().size(), learner.hac()->low_replay().size());
  EXPECT_EQ(restored.hac()->high_replay().size(), learner.hac()->high_replay().size());
  // a checkpoint without the high level (another method's) is refused
  config::Config sac_her = HacRun();
  sac_her.run.method = config::Method::kSacHer;
  Learner flat(LearnerOptionsFor(sac_her, rl::RunShapeFor(sac_her)));
  flat.SaveCheckpoint(path);
  EXPECT_THROW(restored.LoadCheckpoint(path), nn::CheckpointError);
  std::filesystem::remove(path);
}

// `srics eval` loads only the acting networks: both levels of a HAC checkpoint, as the actors
// build them, and refuses files that do not fit.
TEST(ActingPolicyTest, LoadsBothLevelsOfAHacCheckpointAndRefusesOthers) {
  const std::string path = ::testing::TempDir() + "/hac_acting.srics";
  const config::Config run = HacRun();
  Learner learner(LearnerOptionsFor(run, rl::RunShapeFor(run)));
  for (int i = 0; i < 30; ++i) ASSERT_EQ(learner.Ingest(HandEpisode()), "");
  for (int i = 0; i < 2; ++i) learner.Update();
  learner.SaveCheckpoint(path);
  nn::Rng rng(7);
  rl::PolicyNetwork<float> low("policy", rl::MakeNetworkConfig(rl::AgentShapeFor(run.env, run.run.method), run.agent),
                               rng);
  rl::PolicyNetwork<float> high("policy", rl::MakeNetworkConfig(rl::HighLevelShapeFor(run.env), run.agent), rng);
  ASSERT_NE(nn::Flatten(low.Parameters()), learner.agent().PolicyWeights());
  const LearnerCounters counters = LoadActingPolicies(path, low, &high);
  EXPECT_EQ(nn::Flatten(low.Parameters()), learner.agent().PolicyWeights());
  EXPECT_EQ(nn::Flatten(high.Parameters()), learner.hac()->high().PolicyWeights());
  EXPECT_EQ(counters.updates, 2u);
  EXPECT_EQ(counters, learner.counters());

  // another architecture (a table with more pucks): refused, naming the file
  config::Config bigger = run;
  bigger.env.num_pucks = 3;
  rl::PolicyNetwork<float> other("policy",
                                 rl::MakeNetworkConfig(rl::AgentShapeFor(bigger.env, run.run.method), run.agent), rng);
  try {
    LoadActingPolicies(path, other, nullptr);
    ADD_FAILURE() << "loaded into another architecture";
  } catch (const nn::CheckpointError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(path));
  }
  // a flat method's checkpoint has no high level
  config::Config sac_her = run;
  sac_her.run.method = config::Method::kSacHer;
  Learner flat(LearnerOptionsFor(sac_her, rl::RunShapeFor(sac_her)));
  flat.SaveCheckpoint(path);
  EXPECT_THROW(LoadActingPolicies(path, low, &high), nn::CheckpointError);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace srics::learner
