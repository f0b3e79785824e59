#include "actor/rollout.h"

#include <array>
#include <vector>

#include "actor/env/sampling.h"
#include "common/rl/goal_token.h"
#include "common/rl/rewards.h"
#include "common/rl/seeds.h"

namespace srics::actor {
namespace {

// Keeps the current entity states in both the float matrix the policy reads and the episode.
class Observer {
 public:
  explicit Observer(const env::Environment& env) : layout_(LayoutOf(env)) {}

  // Reads the environment's states into entities_ (N x D).
  const nn::Tensor& Observe(const env::Environment& env) {
    env.GetStates(&buffer_);
    entities_.resize(layout_.num_entities, layout_.entity_dim());
    for (size_t i = 0; i < buffer_.size(); ++i) entities_.data()[i] = static_cast<float>(buffer_[i]);
    return entities_;
  }
  void Append(std::vector<float>* states) const {
    states->insert(states->end(), entities_.data(), entities_.data() + entities_.size());
  }
  const rl::EntityLayout& layout() const { return layout_; }
  const nn::Tensor& entities() const { return entities_; }

 private:
  rl::EntityLayout layout_;
  std::vector<double> buffer_;
  nn::Tensor entities_;
};

rl::Episode StartEpisode(const env::Environment& env, const rl::EntityLayout& layout) {
  rl::Episode episode;
  episode.layout = layout;
  for (int kind : env.layout().kinds) episode.entity_kinds.push_back(static_cast<uint16_t>(kind));
  episode.action_dim = env.action_dim();
  return episode;
}

// Steps with a float action; false when the physics became unstable.
bool StepWith(env::Environment& env, const float* action, int dim, std::vector<float>* actions) {
  std::array<double, 8> a{};
  for (int i = 0; i < dim; ++i) a[i] = action[i];
  if (actions) actions->insert(actions->end(), action, action + dim);
  return env.Step(std::span<const double>(a.data(), dim)) == env::StepStatus::kOk;
}

nn::Tensor FullGoalToken(const env::Environment& env) {
  const auto& goals = env.goals();
  nn::Tensor token(1, 2 * goals.size());
  for (size_t j = 0; j < goals.size(); ++j) {
    token(0, 2 * j) = static_cast<float>(goals[j][0]);
    token(0, 2 * j + 1) = static_cast<float>(goals[j][1]);
  }
  return token;
}

}  // namespace

TrainOptions TrainOptionsFor(const config::Config& config) {
  TrainOptions train;
  train.steps = config.actors.train_episode_steps;
  train.full_goal = config.run.method == config::Method::kSacHer;
  train.sampling = config.env.sampling;
  return train;
}

EvalOptions EvalOptionsFor(const config::Config& config) {
  const config::Method method = config.run.method;
  EvalOptions eval;
  eval.attempt_steps = config.actors.eval_attempt_steps;
  eval.full_goal = method == config::Method::kSacHer;
  eval.threshold = config.env.success_threshold;
  eval.epsilon = config.agent.reward.epsilon;
  eval.order = (method == config::Method::kSrics || method == config::Method::kSricsNoSelectivity)
                   ? rl::SubgoalOrder::kDepth
                   : rl::SubgoalOrder::kRandom;
  return eval;
}

rl::EntityLayout LayoutOf(const env::Environment& env) {
  const env::EntityLayout& l = env.layout();
  return {l.num_entities, l.num_kinds, l.velocities};
}

std::optional<rl::Episode> RunExploreEpisode(env::Environment& env, int steps, uint64_t seed,
                                             nn::Rng& rng) {
  env.Reset(seed);
  Observer observer(env);
  rl::Episode episode = StartEpisode(env, observer.layout());
  episode.mode = rl::EpisodeMode::kExplore;
  episode.num_steps = steps;
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::vector<float> action(env.action_dim());
  observer.Observe(env);
  observer.Append(&episode.states);
  for (int t = 0; t < steps; ++t) {
    for (float& a : action) a = uniform(rng);
    if (!StepWith(env, action.data(), env.action_dim(), &episode.actions)) return std::nullopt;
    observer.Observe(env);
    observer.Append(&episode.states);
  }
  return episode;
}

std::optional<rl::Episode> RunTrainEpisode(env::Environment& env, rl::PolicyNetwork<float>& policy,
                                           const rl::SubgoalStructure& structure,
                                           const TrainOptions& options, uint64_t seed,
                                           nn::Rng& rng) {
  env.Reset(seed);
  Observer observer(env);
  const rl::EntityLayout& layout = observer.layout();
  rl::Episode episode = StartEpisode(env, layout);
  episode.mode = rl::EpisodeMode::kTrain;
  episode.num_steps = options.steps;
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
    const env::Vec2 g = env::SampleSubgoal(options.sampling, rng);
    episode.subgoal_entity = entity;
    episode.goal = {static_cast<float>(g[0]), static_cast<float>(g[1])};
    episode.ancestor_mask = entity < structure.num_entities() ? structure.ancestor_mask[entity] : 0;
    goal.resize(1, rl::SubgoalTokenSize(layout.num_kinds));
    rl::WriteSubgoalToken(layout.num_kinds, episode.entity_kinds[entity], episode.goal[0],
                          episode.goal[1], goal.data());
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

std::optional<rl::EpisodeMetrics> RunEvaluationEpisode(env::Environment& env,
                                                       rl::PolicyNetwork<float>* policy,
                                                       const rl::SubgoalStructure& structure,
                                                       const EvalOptions& options, uint64_t seed) {
  env.Reset(seed, env::Split::kEval);
  Observer observer(env);
  const rl::EntityLayout& layout = observer.layout();
  nn::Rng rng(seed ^ 0x9e3779b97f4a7c15ull);
  std::vector<float> zero(env.action_dim(), 0.0f);
  std::vector<float> before;
  double selectivity_sum = 0;
  int selectivity_steps = 0;

  // one attempt: `steps` steps towards `goal` (a token), measuring selectivity for `entity`
  auto attempt = [&](const nn::Tensor& goal, int entity, int steps) {
    for (int t = 0; t < steps; ++t) {
      observer.Observe(env);
      before.assign(observer.entities().data(), observer.entities().data() + observer.entities().size());
      const float* action = policy ? policy->Act(observer.entities(), goal, true, rng).data() : zero.data();
      if (!StepWith(env, action, env.action_dim(), nullptr)) return false;
      if (entity >= 0) {
        const nn::Tensor& after = observer.Observe(env);
        const uint64_t ancestors = entity < structure.num_entities() ? structure.ancestor_mask[entity] : 0;
        if (auto m = rl::SelectivityMeasure(layout, before.data(), after.data(), entity, ancestors,
                                            options.epsilon)) {
          selectivity_sum += *m;
          ++selectivity_steps;
        }
      }
    }
    return true;
  };

  if (options.full_goal) {
    if (!attempt(FullGoalToken(env), -1, (2 * layout.num_entities - 1) * options.attempt_steps))
      return std::nullopt;
  } else {
    std::mt19937_64 order_rng(seed);
    nn::Tensor goal(1, rl::SubgoalTokenSize(layout.num_kinds));
    for (int entity : rl::EvaluationSchedule(structure, options.order, order_rng)) {
      if (entity >= layout.num_entities) continue;
      // solved subgoals are skipped
      if (env.ComputeMetrics().distances[entity] < options.threshold) continue;
      const env::Vec2& g = env.goals()[entity];
      rl::WriteSubgoalToken(layout.num_kinds, env.layout().kinds[entity], static_cast<float>(g[0]),
                            static_cast<float>(g[1]), goal.data());
      if (!attempt(goal, entity, options.attempt_steps)) return std::nullopt;
    }
  }
  const env::Metrics m = env.ComputeMetrics();
  rl::EpisodeMetrics out;
  out.entity_distance = m.distances;
  out.avg_distance = m.avg_distance;
  out.avg_object_distance = m.avg_object_distance;
  out.success = m.success;
  out.selectivity = selectivity_steps ? selectivity_sum / selectivity_steps : -1.0;
  return out;
}

rl::EvaluationSummary EvaluatePolicy(env::Environment& env, rl::PolicyNetwork<float>* policy,
                                     const rl::SubgoalStructure& structure, const EvalOptions& options,
                                     int episodes, uint64_t run_seed, uint64_t* unstable) {
  rl::EvaluationSummary summary;
  for (int i = 0; i < episodes; ++i) {
    const auto metrics = RunEvaluationEpisode(env, policy, structure, options, rl::EvalEpisodeSeed(run_seed, i));
    if (metrics) summary.Add(*metrics, options.threshold);
    else ++*unstable;
  }
  return summary;
}

}  // namespace srics::actor
