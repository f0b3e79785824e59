#pragma once
// Training episodes: one independently controllable subgoal per episode (SRICS, SMORL and the
// ablations), the full goal (SAC+HER), or HAC's two levels; from a reset, or where the last
// episode left the table (actors.train_chain_episodes).

#include <cstdint>
#include <optional>

#include "actor/env/environment.h"
#include "actor/hac_acting.h"
#include "common/config/env_config.h"
#include "common/nn/tensor.h"
#include "common/rl/episode.h"
#include "common/rl/graph.h"
#include "common/rl/networks.h"

namespace srics::actor {

struct TrainOptions {
  int steps = 20;                    // episode length (HAC: the longest, H * H)
  bool full_goal = false;            // SAC+HER: the environment's full goal instead of a subgoal
  config::SamplingConfig sampling;   // subgoal goal region
  std::optional<HacActOptions> hac;  // set for HAC: two levels on the full goal
  int chain_episodes = 1;            // consecutive episodes per reset (actors.train_chain_episodes; not HAC)
};

// Where a training episode starts.
enum class TrainStart {
  kReset,          // a reset of the table with the episode's seed
  kWhereTheEnvIs,  // the state the last episode left (a chain: actors.train_chain_episodes)
};

// One training episode: a subgoal entity drawn uniformly among the subgoal entities of this
// episode's structure (subgoals.For the present entities' catalogue identities), its goal from the subgoal region,
// actions sampled from the policy. The episode records the subgoal, goal and ancestor mask. Empty if the physics became
// unstable.
std::optional<rl::Episode> RunTrainEpisode(env::Environment& env, rl::PolicyNetwork<float>& policy,
                                           const rl::CatalogueSubgoals& subgoals, const TrainOptions& options,
                                           uint64_t seed, nn::Rng& rng, TrainStart start = TrainStart::kReset);

// HAC's training episode: the high level proposes `horizon` subgoals (the xy of every entity)
// for the environment's full goal; the low level pursues each for `horizon` steps at most,
// ending early when it reaches the subgoal or the full goal. Each subgoal is a test subgoal
// with test_probability (the low level then takes its mean action). The episode records the
// full goal, the subgoals, where each started and which were tests. Empty if the physics
// became unstable.
std::optional<rl::Episode> RunHacTrainEpisode(env::Environment& env, rl::PolicyNetwork<float>& high,
                                              rl::PolicyNetwork<float>& low, const HacActOptions& options,
                                              uint64_t seed, nn::Rng& rng);

}  // namespace srics::actor
