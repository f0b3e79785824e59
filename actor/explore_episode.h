#pragma once
// Explore episodes: uniformly random actions (the graph service's data, the paper's) or, for
// a share of them, noisy pushes of random objects toward random targets.

#include <cstdint>
#include <optional>

#include "actor/env/environment.h"
#include "actor/env/scripted_policy.h"
#include "common/nn/tensor.h"
#include "common/rl/episode.h"

namespace srics::actor {

// How explore episodes act (actors.explore_* of the config).
struct ExploreOptions {
  int steps = 50;
  double push_fraction = 0;               // share of episodes driven by the pushing controller
  int push_segment_steps = 10;            // steps per (object, target) pair
  double push_noise = 0.3;                // std of the Gaussian noise on each action component
  env::PushGeometry push;                 // hand and object geometry (the largest object of the table)
  env::Vec2 target_low{}, target_high{};  // targets are drawn in this box (the subgoal box)
};

// Reset(seed), then `steps` steps of uniformly random actions or, for a push_fraction share
// of the episodes, of noisy pushes of random objects toward random targets. Empty if the
// physics became unstable (such an episode is never passed on).
std::optional<rl::Episode> RunExploreEpisode(env::Environment& env, const ExploreOptions& options, uint64_t seed,
                                             nn::Rng& rng);
// Uniformly random actions only.
std::optional<rl::Episode> RunExploreEpisode(env::Environment& env, int steps, uint64_t seed, nn::Rng& rng);

}  // namespace srics::actor
