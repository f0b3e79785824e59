#include "actor/train_episode.h"

#include <random>
#include <vector>

#include "actor/env/sampling.h"
#include "actor/episode_parts.h"
#include "common/rl/goal_token.h"

namespace srics::actor {

std::optional<rl::Episode> RunTrainEpisode(env::Environment& env, rl::PolicyNetwork<float>& policy,
                                           const rl::CatalogueSubgoals& subgoals, const TrainOptions& options,
                                           uint64_t seed, nn::Rng& rng, TrainStart start) {
  if (start == TrainStart::kReset) env.Reset(seed);
  Observer observer(env);
  const rl::EntityLayout& layout = observer.layout();
  rl::Episode episode = StartEpisode(env, layout);
  episode.mode = rl::EpisodeMode::kTrain;
  episode.num_steps = options.steps;
  // the catalogue graph mapped onto the objects this reset drew: indices are the episode's
  const rl::SubgoalStructure structure = subgoals.For(episode.entity_kinds);
  nn::Tensor goal;
  if (options.full_goal) {
    goal = FullGoalToken(env);
    episode.goal.assign(goal.data(), goal.data() + goal.size());
  } else {
    std::vector<int> candidates;
    for (int i : structure.SubgoalEntities())
      if (i < layout.num_entities) candidates.push_back(i);
    if (candidates.empty()) candidates.push_back(0);
    const int entity = candidates[env::UniformIndex(rng, candidates.size())];
    // a tied pair attempted as one (graph.object_ties: joint): a goal for each of its objects
    const rl::SubgoalUnit subgoal = structure.UnitOf(entity);
    episode.subgoal_entity = entity;
    episode.goal.clear();
    for (int m = 0; m < subgoal.size(); ++m) {
      const env::Vec2 g = env::SampleSubgoal(options.sampling, rng);
      episode.goal.push_back(static_cast<float>(g[0]));
      episode.goal.push_back(static_cast<float>(g[1]));
    }
    episode.ancestor_mask = entity < structure.num_entities() ? structure.ancestor_mask[entity] : 0;
    const int tokens = policy.config().goal_tokens;
    goal.resize(1, tokens * rl::SubgoalTokenSize(layout.num_kinds));
    rl::WriteSubgoalTokens(layout.num_kinds, tokens, subgoal, episode.entity_kinds, episode.goal.data(), goal.data());
  }
  observer.Observe(env);
  observer.Append(&episode.states);
  for (int t = 0; t < options.steps; ++t) {
    const nn::Tensor& action = policy.Act(observer.entities(), goal, false, rng);
    if (!StepWith(env, action.data(), env.action_dim(), &episode.actions)) return std::nullopt;
    observer.Observe(env);
    observer.Append(&episode.states);
  }
  return episode;
}

std::optional<rl::Episode> RunHacTrainEpisode(env::Environment& env, rl::PolicyNetwork<float>& high,
                                              rl::PolicyNetwork<float>& low, const HacActOptions& options,
                                              uint64_t seed, nn::Rng& rng) {
  env.Reset(seed);
  Observer observer(env);
  const rl::EntityLayout& layout = observer.layout();
  rl::Episode episode = StartEpisode(env, layout);
  episode.mode = rl::EpisodeMode::kTrain;
  const nn::Tensor goal = PaddedFullGoalToken(env, high.config().goal_dim);
  episode.goal.assign(goal.data(), goal.data() + 2 * layout.num_entities);
  HacActor actor(high, low, options, layout, goal);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  observer.Observe(env);
  observer.Append(&episode.states);
  int t = 0;
  for (int k = 0; k < options.horizon; ++k) {
    const bool test = unit(rng) < options.test_probability;
    const std::vector<float>& subgoal = actor.Propose(observer.entities(), false, test, rng);
    episode.subgoal_starts.push_back(static_cast<uint16_t>(t));
    episode.subgoals.insert(episode.subgoals.end(), subgoal.begin(), subgoal.end());
    episode.subgoal_tests.push_back(test ? 1 : 0);
    do {
      const nn::Tensor& action = actor.Act(observer.entities(), false, rng);
      if (!StepWith(env, action.data(), env.action_dim(), &episode.actions)) return std::nullopt;
      observer.Observe(env);
      observer.Append(&episode.states);
      ++t;
    } while (!actor.SubgoalOver(observer.entities()));
  }
  episode.num_steps = t;
  return episode;
}

}  // namespace srics::actor
