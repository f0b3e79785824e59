// Task-level behaviour: a scripted pusher solves single-puck episodes, a random policy does
// not; the scripted pusher also works with the other object shapes.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "actor/env/rearrange_env.h"
#include "actor/env/scripted_policy.h"
#include "common/config/config.h"
#include "tests/actor/env/env_presets.h"

namespace srics::env {
namespace {

using testing::Preset;

constexpr int kEpisodes = 20;
constexpr int kSteps = 60;

// Number of the 20 seeded episodes whose puck ends within 0.05 of its goal.
template <typename Policy>
int Solved(RearrangeEnv& env, Policy policy, double* mean_distance) {
  int solved = 0;
  *mean_distance = 0;
  for (int seed = 0; seed < kEpisodes; ++seed) {
    env.Reset(1000 + seed);
    for (int t = 0; t < kSteps; ++t) {
      const auto p = env.Positions();
      EXPECT_EQ(env.Step(policy(p, env.goals())), StepStatus::kOk);
    }
    const auto p = env.Positions();
    const double d = std::hypot(p[1][0] - env.goals()[1][0], p[1][1] - env.goals()[1][1]);
    *mean_distance += d / kEpisodes;
    solved += d < 0.05;
  }
  return solved;
}

TEST(BehaviourTest, ScriptedPusherSolvesMostRandomPolicyDoesNot) {
  const config::EnvConfig c = Preset("rearrange-1");
  RearrangeEnv env(c);
  const PushGeometry g = MakePushGeometry(c, 1);
  double pusher_distance = 0, random_distance = 0;
  const int pusher = Solved(
      env,
      [&](const std::vector<Vec2>& p, const std::vector<Vec2>& goals) { return PushAction(p[0], p[1], goals[1], g); },
      &pusher_distance);
  Rng rng(5);
  const int random = Solved(
      env,
      [&](const std::vector<Vec2>&, const std::vector<Vec2>&) {
        return Vec2{Uniform(rng, -1, 1), Uniform(rng, -1, 1)};
      },
      &random_distance);
  std::printf("pusher: %d/%d within 0.05 (mean final distance %.3f); random: %d/%d (%.3f)\n", pusher, kEpisodes,
              pusher_distance, random, kEpisodes, random_distance);
  EXPECT_GE(pusher, 14);
  EXPECT_LE(random, 3);
  EXPECT_LT(pusher_distance, 0.5 * random_distance);
}

TEST(BehaviourTest, ScriptedPusherMovesABoxToo) {
  config::EnvConfig c = Preset("rearrange-1");
  c.objects = {config::ObjectConfig{}};
  c.objects[0].shape = config::ObjectShape::kBox;
  c.objects[0].size = 0.03;
  RearrangeEnv env(c);
  const PushGeometry g = MakePushGeometry(c, 1);
  double distance = 0;
  const int solved = Solved(
      env,
      [&](const std::vector<Vec2>& p, const std::vector<Vec2>& goals) { return PushAction(p[0], p[1], goals[1], g); },
      &distance);
  std::printf("pusher on a box: %d/%d (mean final distance %.3f)\n", solved, kEpisodes, distance);
  EXPECT_GE(solved, 10);
}

}  // namespace
}  // namespace srics::env
