// rl::ValidateEpisode and rl::EpisodeLimitsFor on hand-made episodes: for each rule a value
// just inside passes and one just outside fails with a reason naming the field.

#include "common/rl/episode.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/rl/agent_shape.h"

namespace srics::rl {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// A whole train episode: `entities` entities of kinds 0, 1, ..., positions 0.1 m apart.
Episode MakeValid(int entities = 3, int kinds = 5, bool velocities = false, int steps = 4) {
  Episode e;
  e.layout = {entities, kinds, velocities};
  e.num_steps = steps;
  e.action_dim = 2;
  for (int i = 0; i < entities; ++i) e.entity_kinds.push_back(static_cast<uint16_t>(i));
  const int d = e.layout.entity_dim();
  for (int t = 0; t <= steps; ++t)
    for (int i = 0; i < entities; ++i)
      for (int k = 0; k < d; ++k)
        e.states.push_back(k < kinds ? (k == i ? 1.0f : 0.0f) : 0.1f * static_cast<float>(i + k - kinds));
  e.actions.assign(static_cast<size_t>(steps) * 2, 0.5f);
  e.subgoal_entity = 1;
  e.goal = {0.05f, 0.6f};
  e.ancestor_mask = 1;
  e.mode = EpisodeMode::kTrain;
  return e;
}

// The limits of MakeValid's default layout, with an entity count in [2, 4].
EpisodeLimits Limits() {
  EpisodeLimits limits = LimitsOfLayout(MakeValid().layout, 2);
  limits.min_entities = 2;
  limits.max_entities = 4;
  return limits;
}

// Index of entity i's column k at step t.
size_t At(const Episode& e, int t, int entity, int column) {
  return (static_cast<size_t>(t) * e.layout.num_entities + entity) * e.layout.entity_dim() + column;
}

#define EXPECT_VALID(episode, limits) EXPECT_EQ(ValidateEpisode(episode, limits), "")
// Refused, and the reason names `field`.
#define EXPECT_REFUSED(episode, limits, field)                                        \
  do {                                                                                \
    const std::string reason = ValidateEpisode(episode, limits);                      \
    EXPECT_NE(reason.find(field), std::string::npos) << "reason: '" << reason << "'"; \
  } while (0)

TEST(EpisodeLimitsTest, AValidEpisodePasses) { EXPECT_VALID(MakeValid(), Limits()); }

TEST(EpisodeLimitsTest, EntityCountWithinTheRunsRange) {
  EXPECT_VALID(MakeValid(2), Limits());
  EXPECT_VALID(MakeValid(4), Limits());
  EXPECT_REFUSED(MakeValid(1), Limits(), "num_entities");
  EXPECT_REFUSED(MakeValid(5), Limits(), "num_entities");
  // never beyond the contract's 64 (ancestor masks), whatever the limits say
  EpisodeLimits wide = Limits();
  wide.num_kinds = 0;
  wide.max_entities = 1000;
  EXPECT_VALID(MakeValid(kMaxEntities, kMaxEntities), wide);
  EXPECT_REFUSED(MakeValid(kMaxEntities + 1, kMaxEntities), wide, "num_entities");
}

TEST(EpisodeLimitsTest, KindsVelocitiesAndActionSizeAreTheRuns) {
  EXPECT_REFUSED(MakeValid(3, 4), Limits(), "num_kinds");
  EXPECT_REFUSED(MakeValid(3, 6), Limits(), "num_kinds");
  EXPECT_REFUSED(MakeValid(3, 5, /*velocities=*/true), Limits(), "velocities");
  Episode e = MakeValid();
  e.action_dim = 3;
  e.actions.assign(e.num_steps * 3, 0.0f);
  EXPECT_REFUSED(e, Limits(), "action_dim");
  // "any" in the default limits, within the contract
  EpisodeLimits any;
  EXPECT_VALID(e, any);
  e.action_dim = kMaxActionDim + 1;
  e.actions.assign(static_cast<size_t>(e.num_steps) * e.action_dim, 0.0f);
  EXPECT_REFUSED(e, any, "action_dim");
}

TEST(EpisodeLimitsTest, StepCountOneToTheContractsMaximum) {
  EXPECT_VALID(MakeValid(2, 5, false, 1), Limits());
  EXPECT_REFUSED(MakeValid(2, 5, false, 0), Limits(), "num_steps");
  EXPECT_VALID(MakeValid(2, 5, false, kMaxEpisodeSteps), Limits());
  EXPECT_REFUSED(MakeValid(2, 5, false, kMaxEpisodeSteps + 1), Limits(), "num_steps");
  EpisodeLimits shorter = Limits();
  shorter.max_steps = 50;
  EXPECT_VALID(MakeValid(2, 5, false, 50), shorter);
  EXPECT_REFUSED(MakeValid(2, 5, false, 51), shorter, "num_steps");
}

TEST(EpisodeLimitsTest, ModeIsOneOfTheThree) {
  Episode e = MakeValid();
  e.mode = EpisodeMode::kEval;
  EXPECT_VALID(e, Limits());
  e.mode = static_cast<EpisodeMode>(3);
  EXPECT_REFUSED(e, Limits(), "mode");
}

TEST(EpisodeLimitsTest, SizesFollowTheLayout) {
  const Episode good = MakeValid();
  Episode e = good;
  e.states.pop_back();
  EXPECT_REFUSED(e, Limits(), "states");
  e = good;
  e.actions.push_back(0);
  EXPECT_REFUSED(e, Limits(), "actions");
  e = good;
  e.entity_kinds.pop_back();
  EXPECT_REFUSED(e, Limits(), "entity_kinds");
}

TEST(EpisodeLimitsTest, EntityKindsBelowNumKindsAndOneHotInTheStates) {
  Episode e = MakeValid();
  // entity 2 becomes kind 4 (the last one): its identifier column moves with it
  e.entity_kinds[2] = 4;
  for (int t = 0; t <= e.num_steps; ++t) {
    e.states[At(e, t, 2, 2)] = 0.0f;
    e.states[At(e, t, 2, 4)] = 1.0f;
  }
  EXPECT_VALID(e, Limits());
  e.entity_kinds[2] = 5;
  EXPECT_REFUSED(e, Limits(), "entity_kinds[2]");
  e = MakeValid();
  e.states[At(e, 3, 1, 1)] = 0.999f;
  EXPECT_REFUSED(e, Limits(), "identifier");
  e = MakeValid();
  e.states[At(e, 0, 0, 3)] = 1.0f;  // a second one in entity 0's identifier
  EXPECT_REFUSED(e, Limits(), "states[3]");
}

TEST(EpisodeLimitsTest, PositionsAndVelocitiesAreBounded) {
  Episode e = MakeValid();
  const size_t x = At(e, 2, 1, 5);
  e.states[x] = kMaxAbsPosition;
  EXPECT_VALID(e, Limits());
  e.states[x] = -kMaxAbsPosition;
  EXPECT_VALID(e, Limits());
  e.states[x] = std::nextafter(kMaxAbsPosition, 2 * kMaxAbsPosition);
  EXPECT_REFUSED(e, Limits(), "states[" + std::to_string(x) + "]");
  e.states[x] = 1e30f;  // finite, and poison for the networks
  EXPECT_REFUSED(e, Limits(), "outside");

  EpisodeLimits with_velocities = Limits();
  with_velocities.velocities = true;
  e = MakeValid(3, 5, true);
  const size_t vy = At(e, 1, 2, 8);
  e.states[vy] = -kMaxAbsVelocity;
  EXPECT_VALID(e, with_velocities);
  e.states[vy] = -std::nextafter(kMaxAbsVelocity, 2 * kMaxAbsVelocity);
  EXPECT_REFUSED(e, with_velocities, "states[" + std::to_string(vy) + "]");
}

TEST(EpisodeLimitsTest, EveryValueIsFinite) {
  const Episode good = MakeValid();
  Episode e = good;
  e.states.back() = kNaN;
  EXPECT_REFUSED(e, Limits(), "not finite");
  e = good;
  e.actions[0] = kInf;
  EXPECT_REFUSED(e, Limits(), "actions[0]");
  e = good;
  e.goal[1] = -kInf;
  EXPECT_REFUSED(e, Limits(), "goal[1]");
}

TEST(EpisodeLimitsTest, ActionsWithinPlusMinusOne) {
  Episode e = MakeValid();
  e.actions[2] = 1.0f;
  e.actions[3] = -1.0f;
  EXPECT_VALID(e, Limits());
  e.actions[2] = std::nextafter(1.0f, 2.0f);
  EXPECT_REFUSED(e, Limits(), "actions[2]");
}

TEST(EpisodeLimitsTest, SubgoalGoalAndAncestorMask) {
  const Episode good = MakeValid();
  Episode e = good;
  e.subgoal_entity = 2;
  EXPECT_VALID(e, Limits());
  e.subgoal_entity = 3;
  EXPECT_REFUSED(e, Limits(), "subgoal_entity");
  e.subgoal_entity = -2;
  EXPECT_REFUSED(e, Limits(), "subgoal_entity");
  e = good;
  e.goal = {1, 2, 3};
  EXPECT_REFUSED(e, Limits(), "goal");
  e = good;  // a full goal is 2N values
  e.subgoal_entity = -1;
  e.goal.assign(2 * e.layout.num_entities, 0.5f);
  EXPECT_VALID(e, Limits());
  e.goal.pop_back();
  EXPECT_REFUSED(e, Limits(), "goal");
  e = good;
  e.goal[0] = kMaxAbsPosition;
  EXPECT_VALID(e, Limits());
  e.goal[0] = std::nextafter(kMaxAbsPosition, 2 * kMaxAbsPosition);
  EXPECT_REFUSED(e, Limits(), "goal[0]");
  e = good;  // explore episodes need no goal, train episodes do
  e.mode = EpisodeMode::kExplore;
  e.goal.clear();
  e.subgoal_entity = -1;
  EXPECT_VALID(e, Limits());
  e.mode = EpisodeMode::kTrain;
  EXPECT_REFUSED(e, Limits(), "goal");
  e = good;
  e.ancestor_mask = 1ull << 2;
  EXPECT_VALID(e, Limits());
  e.ancestor_mask = 1ull << 3;
  EXPECT_REFUSED(e, Limits(), "ancestor_mask");
}

// HAC's subgoal record: 2 subgoals over 4 steps, starts 0 and 2, H = 2.
TEST(EpisodeLimitsTest, HacSubgoalsStartAtZeroIncreaseAndFitTheHorizon) {
  Episode good = MakeValid();
  good.subgoal_entity = -1;
  good.goal.assign(6, 0.5f);
  good.subgoal_starts = {0, 2};
  good.subgoals.assign(2 * 6, 0.3f);
  good.subgoal_tests = {0, 1};
  EpisodeLimits limits = Limits();
  limits.max_subgoal_steps = 2;
  EXPECT_VALID(good, limits);
  Episode e = good;
  e.subgoal_starts = {1, 2};
  EXPECT_REFUSED(e, limits, "subgoal_starts[0] = 1, must be 0");
  e.subgoal_starts = {0, 0};
  EXPECT_REFUSED(e, limits, "subgoal_starts[0] = 0: not below the next start 0");
  e = good;
  e.subgoal_starts = {0, 2, 4};  // the last starts at T
  EXPECT_REFUSED(e, limits, "subgoal_starts[2] = 4: not below num_steps 4");
  e.subgoal_starts = {0, 3};  // the first is held 3 steps
  EXPECT_REFUSED(e, limits, "subgoal 0 held 3 steps, this run allows 2");
  limits.max_subgoal_steps = 0;  // any length
  EXPECT_VALID(e, limits);
  limits.max_subgoal_steps = kNoSubgoals;
  EXPECT_REFUSED(e, limits, "this run's episodes carry no subgoals");
  limits.max_subgoal_steps = 2;
  e = good;
  e.subgoals.pop_back();
  EXPECT_REFUSED(e, limits, "subgoals has 11 values, expected 12 (K x 2N)");
  e = good;
  e.subgoals[5] = kNaN;
  EXPECT_REFUSED(e, limits, "subgoals[5] = nan is not finite");
  e.subgoals[5] = 11;
  EXPECT_REFUSED(e, limits, "subgoals[5]");
  e = good;
  e.subgoal_tests = {0};
  EXPECT_REFUSED(e, limits, "subgoal_tests has 1 values, expected 2");
  e.subgoal_tests = {0, 2};
  EXPECT_REFUSED(e, limits, "subgoal_tests[1] = 2, must be 0 or 1");
  e = good;
  e.mode = EpisodeMode::kExplore;
  EXPECT_REFUSED(e, limits, "subgoal_starts in a non-training episode");
  e = MakeValid();
  e.subgoal_tests = {1};
  EXPECT_REFUSED(e, limits, "without subgoal_starts");
}

TEST(EpisodeLimitsTest, LimitsForAnEnvironmentFollowItsObjectSets) {
  config::EnvConfig env;
  env.objects.resize(4);
  env.velocities = true;
  EpisodeLimits limits = EpisodeLimitsFor(env);
  EXPECT_EQ(limits.min_entities, 5);  // no sets: every object, and the arm
  EXPECT_EQ(limits.max_entities, 5);
  EXPECT_EQ(limits.num_kinds, 5);
  EXPECT_TRUE(limits.velocities);
  EXPECT_EQ(limits.action_dim, 2);
  EXPECT_EQ(limits.max_steps, kMaxEpisodeSteps);

  env.object_sets = {{1, 2, 3}, {2, 3, 4}};  // the 3-of-4 presets
  env.eval_object_sets = {{1, 2}};
  limits = EpisodeLimitsFor(env);
  EXPECT_EQ(limits.min_entities, 3);
  EXPECT_EQ(limits.max_entities, 4);
  EXPECT_EQ(limits.num_kinds, 5);  // kinds span the catalogue, not the set

  env.eval_object_sets.clear();  // evaluation draws from the training sets then
  limits = EpisodeLimitsFor(env);
  EXPECT_EQ(limits.min_entities, 4);
  EXPECT_EQ(limits.max_entities, 4);

  config::EnvConfig pucks;  // the default catalogue: num_pucks pucks
  pucks.num_pucks = 2;
  limits = EpisodeLimitsFor(pucks);
  EXPECT_EQ(limits.min_entities, 3);
  EXPECT_EQ(limits.num_kinds, 3);
  EXPECT_FALSE(limits.velocities);
}

// The vectorized pass that ValidateEpisode and the weights checks run first: every position
// of the vector body and of the tail, each kind of bad value, the bound itself.
TEST(AllFiniteWithinTest, EveryPositionEveryBadValue) {
  std::vector<float> v(37, 0.25f);  // 4 blocks of 8 and a tail of 5
  EXPECT_TRUE(AllFiniteWithin(v.data(), v.size(), 1.0f));
  EXPECT_TRUE(AllFiniteWithin(v.data(), 0, 1.0f));
  for (size_t i = 0; i < v.size(); ++i) {
    for (float bad : {kNaN, kInf, -kInf, std::nextafter(1.0f, 2.0f), -1e30f}) {
      std::vector<float> w = v;
      w[i] = bad;
      EXPECT_FALSE(AllFiniteWithin(w.data(), w.size(), 1.0f)) << "value " << bad << " at " << i;
    }
    std::vector<float> w = v;
    w[i] = -1.0f;  // the bound itself, and -0.0, pass
    w[(i + 1) % w.size()] = -0.0f;
    EXPECT_TRUE(AllFiniteWithin(w.data(), w.size(), 1.0f)) << i;
  }
  // an infinite bound still refuses infinities and NaN, as std::isfinite does
  v[36] = 1e38f;
  EXPECT_TRUE(AllFiniteWithin(v.data(), v.size(), kInf));
  v[36] = kInf;
  EXPECT_FALSE(AllFiniteWithin(v.data(), v.size(), kInf));
  v[36] = kNaN;
  EXPECT_FALSE(AllFiniteWithin(v.data(), v.size(), kInf));
}

// The fast pass over the states must accept what the detailed check accepts and hand every
// refusal to it: each value of a 30-step episode with velocities, broken in turn, is refused
// by name; a -0.0 in an identifier column is a 0 (accepted), a 1 where a 0 belongs is not.
TEST(EpisodeLimitsTest, EveryStateValueIsCheckedAndNamed) {
  EpisodeLimits limits = Limits();
  limits.velocities = true;
  const Episode good = MakeValid(3, 5, true, 30);
  ASSERT_EQ(ValidateEpisode(good, limits), "");
  for (size_t i = 0; i < good.states.size(); ++i) {
    Episode e = good;
    e.states[i] = kNaN;
    EXPECT_REFUSED(e, limits, "states[" + std::to_string(i) + "]");
  }
  Episode e = good;
  e.states[At(e, 7, 2, 0)] = -0.0f;
  EXPECT_VALID(e, limits);
  e.states[At(e, 7, 2, 0)] = 1.0f;
  EXPECT_REFUSED(e, limits, "identifier");
  // the fast pass keeps its pattern between calls: other kinds with the states of the old
  // ones, then other bounds, must not pass on the old pattern
  e = good;
  std::swap(e.entity_kinds[1], e.entity_kinds[2]);
  EXPECT_REFUSED(e, limits, "identifier");
  e = good;
  e.states[At(e, 3, 0, 5)] = 0.5f;
  limits.max_abs_position = 0.4f;
  EXPECT_REFUSED(e, limits, "states[" + std::to_string(At(e, 3, 0, 5)) + "]");
  // an infinite position bound: huge positions pass, infinite ones do not
  limits.max_abs_position = kInf;
  e = good;
  e.states[At(e, 30, 1, 5)] = 1e30f;
  EXPECT_VALID(e, limits);
  e.states[At(e, 30, 1, 5)] = kInf;
  EXPECT_REFUSED(e, limits, "not finite");
}

}  // namespace
}  // namespace srics::rl
