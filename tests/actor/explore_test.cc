// Explore episodes: uniformly random actions, or pushes of random objects toward random
// targets (actors.explore_push_fraction), on the real MuJoCo environment.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "actor/env/rearrange_env.h"
#include "actor/episode_options.h"
#include "actor/explore_episode.h"
#include "common/config/config.h"

namespace srics::actor {
namespace {

// Fraction of transitions in which some object moves more than 1 mm, over `episodes` explore
// episodes; also returns the largest distance an object travelled within one episode.
struct Motion {
  double moving_fraction = 0;
  double largest_travel = 0;
};

Motion Measure(const config::Config& config, double push_fraction, int episodes) {
  auto env = env::MakeRearrangeEnv(config.env);
  ExploreOptions options = ExploreOptionsFor(config);
  options.push_fraction = push_fraction;
  nn::Rng rng(5);
  Motion m;
  int moving = 0, transitions = 0;
  for (int i = 0; i < episodes; ++i) {
    auto episode = RunExploreEpisode(*env, options, 100 + i, rng);
    EXPECT_TRUE(episode.has_value());
    if (!episode) continue;
    const rl::EntityLayout& layout = episode->layout;
    const int n = layout.num_entities;
    auto xy = [&](int t, int e, int a) {
      return episode->states[static_cast<size_t>(t) * layout.state_size() + layout.position_offset(e) + a];
    };
    for (int t = 0; t < episode->num_steps; ++t) {
      bool any = false;
      for (int e = 1; e < n; ++e)
        any |= std::hypot(xy(t + 1, e, 0) - xy(t, e, 0), xy(t + 1, e, 1) - xy(t, e, 1)) > 1e-3;
      moving += any;
      ++transitions;
    }
    for (int e = 1; e < n; ++e) {
      const int last = episode->num_steps;
      m.largest_travel =
          std::max<double>(m.largest_travel, std::hypot(xy(last, e, 0) - xy(0, e, 0), xy(last, e, 1) - xy(0, e, 1)));
    }
  }
  m.moving_fraction = static_cast<double>(moving) / std::max(1, transitions);
  return m;
}

// Pushing episodes touch objects far more often than random actions and carry them further.
TEST(ExploreTest, PushesMoveObjectsMoreThanRandomActions) {
  config::Config config;  // Rearrange 3
  const Motion random = Measure(config, 0.0, 20);
  const Motion pushed = Measure(config, 1.0, 20);
  EXPECT_GT(pushed.moving_fraction, 2 * random.moving_fraction)
      << "random " << random.moving_fraction << ", pushed " << pushed.moving_fraction;
  EXPECT_GT(pushed.largest_travel, 0.1);
  std::printf(
      "objects moving in %.1f%% of transitions with random actions, %.1f%% with pushes; furthest %.2f / %.2f m\n",
      100 * random.moving_fraction, 100 * pushed.moving_fraction, random.largest_travel, pushed.largest_travel);
}

// The same seed and random stream give the same episode; a random-only run keeps its stream
// whatever the push settings (no draw for the episode's kind when pushes are off).
TEST(ExploreTest, DeterministicAndRandomOnlyStreamUnchanged) {
  config::Config config;
  auto env = env::MakeRearrangeEnv(config.env);
  ExploreOptions options = ExploreOptionsFor(config);
  options.push_fraction = 0.5;
  nn::Rng a(9), b(9);
  auto e1 = RunExploreEpisode(*env, options, 42, a);
  auto e2 = RunExploreEpisode(*env, options, 42, b);
  ASSERT_TRUE(e1 && e2);
  EXPECT_EQ(e1->actions, e2->actions);
  EXPECT_EQ(e1->states, e2->states);
  nn::Rng c(9), d(9);
  auto plain = RunExploreEpisode(*env, options.steps, 42, c);
  ExploreOptions off = options;
  off.push_fraction = 0;
  auto off_episode = RunExploreEpisode(*env, off, 42, d);
  ASSERT_TRUE(plain && off_episode);
  EXPECT_EQ(plain->actions, off_episode->actions);
}

}  // namespace
}  // namespace srics::actor
