// The samplers obey their spacing, box and connection rules over many draws, and are pure
// functions of their random generator.

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "actor/env/random_table.h"
#include "actor/env/sampling.h"
#include "common/config/config.h"
#include "tests/actor/env/env_presets.h"

namespace srics::env {
namespace {

using config::EnvConfig;

using testing::Preset;

// Runs 1000 draws of initial positions and goals of `c` and checks every rule.
void CheckThousandDraws(const EnvConfig& c) {
  const auto objects = config::EffectiveObjects(c);
  const Vec2 hand{c.hand.start[0], c.hand.start[1]};
  Rng rng(12345);
  for (int draw = 0; draw < 1000; ++draw) {
    const std::vector<int> present = SampleObjectSet(c, false, rng);
    const auto init = SampleInitialPositions(c, present, rng);
    const auto goals = SampleGoals(c, present, init, rng);
    ASSERT_EQ(init.size(), present.size());
    ASSERT_EQ(goals.size(), present.size() + 1);
    EXPECT_EQ(goals[0], hand);  // the hand's goal is its start
    for (size_t i = 0; i < present.size(); ++i) {
      const double ri = config::BoundingRadius(objects[present[i] - 1]);
      const double extra_i = std::max(0.0, ri - c.sampling.reference_radius);
      // inside the sampling boxes
      EXPECT_GE(init[i][0], c.sampling.init_low[0]);
      EXPECT_LE(init[i][0], c.sampling.init_high[0]);
      EXPECT_GE(init[i][1], c.sampling.init_low[1]);
      EXPECT_LE(init[i][1], c.sampling.init_high[1]);
      EXPECT_GE(goals[i + 1][0], c.sampling.goal_low[0]);
      EXPECT_LE(goals[i + 1][0], c.sampling.goal_high[0]);
      EXPECT_GE(goals[i + 1][1], c.sampling.goal_low[1]);
      EXPECT_LE(goals[i + 1][1], c.sampling.goal_high[1]);
      // away from the hand
      EXPECT_GE(Distance(init[i], hand), c.sampling.init_min_hand_distance + extra_i);
      // a static object's goal kept at its start was placed by the initial rules only
      const auto pinned = [&](size_t k) {
        return objects[present[k] - 1].is_static && !c.sampling.static_object_random_goal;
      };
      if (!pinned(i)) EXPECT_GE(Distance(goals[i + 1], goals[0]), c.sampling.goal_min_hand_distance + extra_i);
      // apart from each other; a tied pair's distance is its tie's (checked below)
      for (size_t j = 0; j < i; ++j) {
        const double rj = config::BoundingRadius(objects[present[j] - 1]);
        bool tied = false;
        for (const auto& link : c.connections)
          tied = tied || (link.first == present[i] && link.second == present[j]) ||
                 (link.first == present[j] && link.second == present[i]);
        if (!tied) {
          EXPECT_GE(Distance(init[i], init[j]),
                    RequiredDistance(c.sampling, c.sampling.init_min_object_distance, ri, rj));
          if (!(pinned(i) && pinned(j)))
            EXPECT_GE(Distance(goals[i + 1], goals[j + 1]),
                      RequiredDistance(c.sampling, c.sampling.goal_min_object_distance, ri, rj));
        }
        EXPECT_GE(Distance(init[i], init[j]), ri + rj);  // never overlapping
        EXPECT_GE(Distance(goals[i + 1], goals[j + 1]), ri + rj);
      }
    }
    // connections: start within the link, goals exactly one link apart
    for (const auto& link : c.connections) {
      int a = -1, b = -1;
      for (size_t k = 0; k < present.size(); ++k) {
        if (present[k] == link.first) a = static_cast<int>(k);
        if (present[k] == link.second) b = static_cast<int>(k);
      }
      ASSERT_GE(a, 0);
      ASSERT_GE(b, 0);
      EXPECT_LE(Distance(init[a], init[b]), link.length + 1e-12);
      EXPECT_NEAR(Distance(goals[a + 1], goals[b + 1]), link.length, 1e-12);
    }
    if (::testing::Test::HasFailure()) FAIL() << "draw " << draw;
  }
}

TEST(SamplingTest, Rearrange4SpacingOverThousandDraws) { CheckThousandDraws(Preset("rearrange-4")); }

TEST(SamplingTest, Relational4RopeRuleOverThousandDraws) { CheckThousandDraws(Preset("relational-4")); }

TEST(SamplingTest, DifferentObjectsOverThousandDraws) { CheckThousandDraws(Preset("different-6")); }

// Six goals of different-6 keep the spacing in about one whole draw of 10,000: with a budget of
// 2,000 whole draws most goal sets used to fail (SamplingError: the graph acceptance's
// different-6 seed 2 died of it at 100,000). Placing one object at a time always finds one.
TEST(SamplingTest, CrowdedTableIsPlacedOneObjectAtATime) {
  EnvConfig c = Preset("different-6");
  c.sampling.max_attempts = 2000;
  CheckThousandDraws(c);
}

// The one-at-a-time placement keeps the rope, the fixed and the static objects' rules too
// (one whole draw, then the fallback). A static object kept at its start may sit closer to
// the hand than a goal may (0.06 against 0.075): every draw used to fail then.
TEST(SamplingTest, OneAtATimeKeepsTheRopeAndStaticRules) {
  for (const char* name : {"relational-4", "relational-4-spring"}) {
    EnvConfig c = Preset(name);
    c.sampling.max_attempts = 1;
    for (bool random_static_goal : {true, false}) {
      c.sampling.static_object_random_goal = random_static_goal;
      SCOPED_TRACE(std::string(name) + (random_static_goal ? " random" : " pinned") + " static goal");
      CheckThousandDraws(c);
      if (random_static_goal) continue;
      const auto objects = config::EffectiveObjects(c);
      Rng rng(7);
      for (int draw = 0; draw < 200; ++draw) {
        const std::vector<int> present = SampleObjectSet(c, false, rng);
        const auto init = SampleInitialPositions(c, present, rng);
        const auto goals = SampleGoals(c, present, init, rng);
        for (size_t k = 0; k < present.size(); ++k)
          if (objects[present[k] - 1].is_static) EXPECT_EQ(goals[k + 1], init[k]);
      }
    }
  }
}

// Random table 5 ties two boxes by a 0.119 m spring, while goals keep 0.133 m between those
// boxes: every goal draw failed, so its environment refused to start (the graph acceptance's
// three table-5 runs). The tie sets a tied pair's distance; it only must not overlap.
TEST(SamplingTest, TiesShorterThanTheGoalSpacingArePlaced) {
  const EnvConfig c = RandomTable(5);
  ASSERT_EQ(c.connections.size(), 1u);
  ASSERT_LT(c.connections[0].length, c.sampling.goal_min_object_distance);
  CheckThousandDraws(c);
}

TEST(SamplingTest, CombinationsOverThousandDraws) { CheckThousandDraws(Preset("rearrange-4-combinations")); }

TEST(SamplingTest, ObjectSetsDrawOnlyTheirSplit) {
  const EnvConfig c = Preset("rearrange-4-combinations");
  Rng rng(7);
  std::set<std::vector<int>> seen;
  for (int i = 0; i < 300; ++i) {
    const auto set = SampleObjectSet(c, false, rng);
    EXPECT_NE(set, (std::vector<int>{2, 3, 4}));  // the held-out one never trains
    seen.insert(set);
  }
  EXPECT_EQ(seen.size(), 3u);  // every training combination comes up
  for (int i = 0; i < 10; ++i) EXPECT_EQ(SampleObjectSet(c, true, rng), (std::vector<int>{2, 3, 4}));
  // no sets: every object
  EXPECT_EQ(SampleObjectSet(Preset("rearrange-3"), false, rng), (std::vector<int>{1, 2, 3}));
}

TEST(SamplingTest, SubgoalsCoverTheirBoxOnly) {
  const config::SamplingConfig s;
  Rng rng(3);
  double min_x = 1, max_x = -1, min_y = 1, max_y = -1;
  for (int i = 0; i < 1000; ++i) {
    const Vec2 g = SampleSubgoal(s, rng);
    min_x = std::min(min_x, g[0]), max_x = std::max(max_x, g[0]);
    min_y = std::min(min_y, g[1]), max_y = std::max(max_y, g[1]);
  }
  EXPECT_GE(min_x, -0.2);
  EXPECT_LE(max_x, 0.2);
  EXPECT_GE(min_y, 0.45);
  EXPECT_LE(max_y, 0.7);
  EXPECT_LT(min_x, -0.19);  // and fills it
  EXPECT_GT(max_x, 0.19);
  EXPECT_LT(min_y, 0.46);
  EXPECT_GT(max_y, 0.69);
}

TEST(SamplingTest, SameGeneratorStateSameSamples) {
  const EnvConfig c = Preset("relational-4");
  Rng a(99), b(99);
  const std::vector<int> present{1, 2, 3, 4};
  const auto ia = SampleInitialPositions(c, present, a);
  const auto ib = SampleInitialPositions(c, present, b);
  EXPECT_EQ(ia, ib);
  EXPECT_EQ(SampleGoals(c, present, ia, a), SampleGoals(c, present, ib, b));
  // and the uniform helper is exactly the documented 53-bit construction
  Rng r(1), s(1);
  EXPECT_EQ(Uniform(r, 0, 1), static_cast<double>(s() >> 11) * 0x1.0p-53);
}

TEST(SamplingTest, StaticObjectGoalCanStayAtItsStart) {
  EnvConfig c = Preset("relational-4");
  c.sampling.static_object_random_goal = false;
  Rng rng(5);
  const std::vector<int> present{1, 2, 3, 4};
  const auto init = SampleInitialPositions(c, present, rng);
  const auto goals = SampleGoals(c, present, init, rng);
  EXPECT_EQ(goals[1], init[0]);
}

}  // namespace
}  // namespace srics::env
