#pragma once
// The actor's episode loops, with no DDS in them: exploration (random actions), training
// (one independently controllable subgoal per episode) and evaluation (a full goal split
// into subgoals, attempted in depth order). Shared by the actor process and the in-process
// trainer, so both behave the same.

#include <cstdint>
#include <optional>

#include "actor/env/environment.h"
#include "common/config/config.h"
#include "common/config/env_config.h"
#include "common/nn/tensor.h"
#include "common/rl/episode.h"
#include "common/rl/evaluation.h"
#include "common/rl/graph.h"
#include "common/rl/networks.h"

namespace srics::actor {

// The rl view of the environment's current layout.
rl::EntityLayout LayoutOf(const env::Environment& env);

// Uniformly random actions for `steps` steps after Reset(seed). Empty if the physics became
// unstable (such an episode is never passed on).
std::optional<rl::Episode> RunExploreEpisode(env::Environment& env, int steps, uint64_t seed,
                                             nn::Rng& rng);

struct TrainOptions {
  int steps = 20;
  bool full_goal = false;  // SAC+HER: the environment's full goal instead of a subgoal
  config::SamplingConfig sampling;  // subgoal goal region
};

// One training episode: a subgoal entity drawn uniformly among the structure's subgoal
// entities, its goal from the subgoal region, actions sampled from the policy. The episode
// records the subgoal, goal and ancestor mask. Empty if the physics became unstable.
std::optional<rl::Episode> RunTrainEpisode(env::Environment& env, rl::PolicyNetwork<float>& policy,
                                           const rl::SubgoalStructure& structure,
                                           const TrainOptions& options, uint64_t seed,
                                           nn::Rng& rng);

struct EvalOptions {
  rl::SubgoalOrder order = rl::SubgoalOrder::kDepth;
  int attempt_steps = 20;
  bool full_goal = false;     // SAC+HER: one attempt of (2N - 1) * attempt_steps on the full goal
  double threshold = 0.05;    // a subgoal counts as solved below this distance
  double epsilon = 1e-5;      // for the selectivity measure
};

// The options a run's config implies (episode lengths, full goal for SAC+HER, subgoal order
// by method: depth for SRICS and its selectivity ablation, random otherwise).
TrainOptions TrainOptionsFor(const config::Config& config);
EvalOptions EvalOptionsFor(const config::Config& config);

// One evaluation episode on the environment's own goals (Reset(seed, kEval)). `policy` null
// is the passive baseline (it never moves). Deterministic policy (its mean action). Returns
// the final-step metrics; empty if the physics became unstable.
std::optional<rl::EpisodeMetrics> RunEvaluationEpisode(env::Environment& env,
                                                       rl::PolicyNetwork<float>* policy,
                                                       const rl::SubgoalStructure& structure,
                                                       const EvalOptions& options, uint64_t seed);

// The evaluation protocol of every mode (actors, the in-process run, `srics eval`): `episodes`
// evaluation episodes with the run's evaluation seeds (rl::EvalEpisodeSeed: the same goals
// at every evaluation, for the policy and the passive baseline alike). Unstable episodes are
// left out of the summary and counted in *unstable.
rl::EvaluationSummary EvaluatePolicy(env::Environment& env, rl::PolicyNetwork<float>* policy,
                                     const rl::SubgoalStructure& structure, const EvalOptions& options,
                                     int episodes, uint64_t run_seed, uint64_t* unstable);

}  // namespace srics::actor
