#include "actor/rollout.h"

#include <cmath>

#include <algorithm>
#include <array>
#include <random>
#include <stdexcept>
#include <vector>

#include "actor/env/sampling.h"
#include "common/profile/phase_clock.h"
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

// Steps with a float action; false when the physics became unstable or the policy gave a
// non-finite action (weights that overflow: the environment would throw on it), so that the
// episode is dropped as unstable instead of ending the actor.
bool StepWith(env::Environment& env, const float* action, int dim, std::vector<float>* actions) {
  std::array<double, 8> a{};
  for (int i = 0; i < dim; ++i) {
    if (!std::isfinite(action[i])) return false;
    a[i] = action[i];
  }
  if (actions) actions->insert(actions->end(), action, action + dim);
  profile::PhaseScope phase(profile::Phase::kEnvStep);
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

// A goal of every entity's xy (2N floats) as a token of `goal_dim` floats (zero padded when
// the episode presents fewer entities than the networks take).
void WriteGoalToken(const float* xy, int num_entities, nn::Tensor* token, int goal_dim) {
  token->setZero(1, goal_dim);
  std::copy(xy, xy + 2 * num_entities, token->data());
}

// HAC's two levels acting on one full goal: the high level proposes a subgoal whenever the
// previous one is over (reached, held H steps, or the full goal reached); the low level acts
// towards the current subgoal.
class HacActor {
 public:
  HacActor(rl::PolicyNetwork<float>& high, rl::PolicyNetwork<float>& low, const HacActOptions& options,
           const rl::EntityLayout& layout, const nn::Tensor& full_goal)
      : high_(high),
        low_(low),
        options_(options),
        layout_(layout),
        full_goal_(full_goal),
        subgoal_(2 * layout.num_entities) {}

  // True when the high level has to propose the next subgoal before the low level acts in
  // state `entities`.
  bool SubgoalOver(const nn::Tensor& entities) const {
    return held_ < 0 || held_ >= options_.horizon ||
           rl::GoalReached(layout_, entities.data(), subgoal_.data(), options_.threshold) ||
           rl::GoalReached(layout_, entities.data(), full_goal_.data(), options_.threshold);
  }
  // The high level's proposal in state `entities`; `test`: the low level then acts without noise.
  const std::vector<float>& Propose(const nn::Tensor& entities, bool deterministic, bool test, nn::Rng& rng) {
    const nn::Tensor& action = high_.Act(entities, full_goal_, deterministic, rng);
    rl::SubgoalFromAction(options_.box, action.data(), layout_.num_entities, subgoal_.data());
    WriteGoalToken(subgoal_.data(), layout_.num_entities, &subgoal_token_, static_cast<int>(full_goal_.cols()));
    held_ = 0;
    test_ = test;
    return subgoal_;
  }
  // The low level's action towards the current subgoal.
  const nn::Tensor& Act(const nn::Tensor& entities, bool deterministic, nn::Rng& rng) {
    ++held_;
    return low_.Act(entities, subgoal_token_, deterministic || test_, rng);
  }

 private:
  rl::PolicyNetwork<float>& high_;
  rl::PolicyNetwork<float>& low_;
  const HacActOptions& options_;
  rl::EntityLayout layout_;
  const nn::Tensor& full_goal_;
  std::vector<float> subgoal_;
  nn::Tensor subgoal_token_;
  int held_ = -1;  // steps the current subgoal was held; -1: none yet
  bool test_ = false;
};

// The environment's full goal as a token for networks taking `goal_dim` floats.
nn::Tensor PaddedFullGoalToken(const env::Environment& env, int goal_dim) {
  const nn::Tensor goal = FullGoalToken(env);
  nn::Tensor token;
  WriteGoalToken(goal.data(), static_cast<int>(goal.cols() / 2), &token, goal_dim);
  return token;
}

}  // namespace

HacActOptions HacActOptionsFor(const config::Config& config) {
  HacActOptions hac;
  hac.horizon = config.agent.hac.horizon;
  hac.test_probability = config.agent.hac.subgoal_test_probability;
  hac.threshold = config.agent.hac.goal_threshold;
  hac.box = rl::SubgoalBoxFor(config.env);
  return hac;
}

TrainOptions TrainOptionsFor(const config::Config& config) {
  TrainOptions train;
  train.steps = config.actors.train_episode_steps;
  train.full_goal = config.run.method == config::Method::kSacHer;
  train.sampling = config.env.sampling;
  train.chain_episodes = config.actors.train_chain_episodes;
  if (config.run.method == config::Method::kHac) {
    train.hac = HacActOptionsFor(config);
    train.steps = train.hac->horizon * train.hac->horizon;
  }
  return train;
}

EvalOptions EvalOptionsFor(const config::Config& config) {
  const config::Method method = config.run.method;
  EvalOptions eval;
  eval.attempt_steps = config.actors.eval_attempt_steps;
  eval.protocol = config.actors.eval_schedule == config::EvalSchedule::kReference
                      ? rl::EvaluationProtocol::kReference
                      : rl::EvaluationProtocol::kIndependentDraws;
  eval.full_goal = method == config::Method::kSacHer || method == config::Method::kHac;
  if (method == config::Method::kHac) eval.hac = HacActOptionsFor(config);
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

ExploreOptions ExploreOptionsFor(const config::Config& config) {
  ExploreOptions o;
  o.steps = config.actors.explore_episode_steps;
  o.push_fraction = config.actors.explore_push_fraction;
  o.push_segment_steps = config.actors.explore_push_segment_steps;
  o.push_noise = config.actors.explore_push_noise;
  // one geometry for every object: the largest keeps the hand clear of all of them
  const auto objects = config::EffectiveObjects(config.env);
  int largest = 1;
  for (size_t i = 0; i < objects.size(); ++i)
    if (config::BoundingRadius(objects[i]) > config::BoundingRadius(objects[largest - 1]))
      largest = static_cast<int>(i) + 1;
  o.push = env::MakePushGeometry(config.env, largest);
  o.target_low = {config.env.sampling.subgoal_low[0], config.env.sampling.subgoal_low[1]};
  o.target_high = {config.env.sampling.subgoal_high[0], config.env.sampling.subgoal_high[1]};
  return o;
}

std::optional<rl::Episode> RunExploreEpisode(env::Environment& env, int steps, uint64_t seed, nn::Rng& rng) {
  ExploreOptions options;
  options.steps = steps;
  return RunExploreEpisode(env, options, seed, rng);
}

std::optional<rl::Episode> RunExploreEpisode(env::Environment& env, const ExploreOptions& options, uint64_t seed,
                                             nn::Rng& rng) {
  env.Reset(seed);
  Observer observer(env);
  rl::Episode episode = StartEpisode(env, observer.layout());
  episode.mode = rl::EpisodeMode::kExplore;
  episode.num_steps = options.steps;
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::normal_distribution<double> noise(0.0, options.push_noise);
  // drawn only when pushes are on, so that random-only runs keep their random streams
  const bool push =
      options.push_fraction > 0 && std::uniform_real_distribution<double>(0, 1)(rng) < options.push_fraction;
  const int objects = env.layout().num_entities - 1;
  std::vector<float> action(env.action_dim());
  observer.Observe(env);
  observer.Append(&episode.states);
  int object = 1;
  env::Vec2 target{};
  for (int t = 0; t < options.steps; ++t) {
    if (push && objects > 0 && action.size() == 2) {
      if (t % options.push_segment_steps == 0) {
        object = 1 + static_cast<int>(std::uniform_int_distribution<int>(0, objects - 1)(rng));
        for (int a = 0; a < 2; ++a)
          target[a] = std::uniform_real_distribution<double>(options.target_low[a], options.target_high[a])(rng);
      }
      const std::vector<env::Vec2> at = env.Positions();
      const env::Vec2 act = env::PushAction(at[0], at[object], target, options.push);
      for (int a = 0; a < 2; ++a) action[a] = static_cast<float>(std::clamp(act[a] + noise(rng), -1.0, 1.0));
    } else {
      for (float& a : action) a = uniform(rng);
    }
    if (!StepWith(env, action.data(), env.action_dim(), &episode.actions)) return std::nullopt;
    observer.Observe(env);
    observer.Append(&episode.states);
  }
  return episode;
}

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
    const env::Vec2 g = env::SampleSubgoal(options.sampling, rng);
    episode.subgoal_entity = entity;
    episode.goal = {static_cast<float>(g[0]), static_cast<float>(g[1])};
    episode.ancestor_mask = entity < structure.num_entities() ? structure.ancestor_mask[entity] : 0;
    goal.resize(1, rl::SubgoalTokenSize(layout.num_kinds));
    rl::WriteSubgoalToken(layout.num_kinds, episode.entity_kinds[entity], episode.goal[0], episode.goal[1],
                          goal.data());
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

std::optional<rl::EpisodeMetrics> RunEvaluationEpisode(env::Environment& env, rl::PolicyNetwork<float>* policy,
                                                       const rl::CatalogueSubgoals& subgoals,
                                                       const EvalOptions& options, uint64_t seed,
                                                       rl::PolicyNetwork<float>* high_policy,
                                                       EvalEpisodeObserver* watcher) {
  env.Reset(seed, env::Split::kEval);
  if (watcher) watcher->OnState(env, -1);
  Observer observer(env);
  const rl::EntityLayout& layout = observer.layout();
  // the held-out combination's own structure, from the catalogue graph
  const rl::SubgoalStructure structure = subgoals.For(env.layout().kinds);
  nn::Rng rng(seed ^ 0x9e3779b97f4a7c15ull);
  std::vector<float> zero(env.action_dim(), 0.0f);
  std::vector<float> before;
  double selectivity_sum = 0;
  int selectivity_steps = 0;
  int independent_solved = 0, independent_undone = 0;

  // one attempt: `steps` steps towards `goal` (a token), measuring selectivity for `entity`
  auto attempt = [&](const nn::Tensor& goal, int entity, int steps) {
    for (int t = 0; t < steps; ++t) {
      observer.Observe(env);
      before.assign(observer.entities().data(), observer.entities().data() + observer.entities().size());
      const float* action = policy ? policy->Act(observer.entities(), goal, true, rng).data() : zero.data();
      if (!StepWith(env, action, env.action_dim(), nullptr)) return false;
      if (watcher) watcher->OnState(env, entity);
      if (entity >= 0) {
        const nn::Tensor& after = observer.Observe(env);
        const uint64_t ancestors = entity < structure.num_entities() ? structure.ancestor_mask[entity] : 0;
        if (auto m = rl::SelectivityMeasure(layout, before.data(), after.data(), entity, ancestors, options.epsilon)) {
          selectivity_sum += *m;
          ++selectivity_steps;
        }
      }
    }
    return true;
  };

  const int full_goal_steps = (2 * layout.num_entities - 1) * options.attempt_steps;
  if (options.hac && policy) {
    // both levels, deterministic, for as many steps as a flat full-goal attempt
    if (!high_policy) throw std::invalid_argument("HAC evaluation needs the high-level policy");
    const nn::Tensor goal = PaddedFullGoalToken(env, high_policy->config().goal_dim);
    HacActor actor(*high_policy, *policy, *options.hac, layout, goal);
    observer.Observe(env);
    for (int t = 0; t < full_goal_steps; ++t) {
      if (actor.SubgoalOver(observer.entities())) actor.Propose(observer.entities(), true, false, rng);
      if (!StepWith(env, actor.Act(observer.entities(), true, rng).data(), env.action_dim(), nullptr))
        return std::nullopt;
      if (watcher) watcher->OnState(env, -1);
      observer.Observe(env);
    }
  } else if (options.full_goal) {
    if (!attempt(FullGoalToken(env), -1, full_goal_steps)) return std::nullopt;
  } else {
    std::mt19937_64 order_rng(seed);
    nn::Tensor goal(1, rl::SubgoalTokenSize(layout.num_kinds));
    const std::vector<int> subgoal_entities = structure.SubgoalEntities();
    int index = 0;
    rl::AttemptSchedule schedule(structure, options.order, options.protocol, order_rng);
    std::vector<double> before_attempt;
    auto solved = [&](int entity) {
      return entity < static_cast<int>(before_attempt.size()) && before_attempt[entity] < options.threshold;
    };
    while (true) {
      before_attempt = env.ComputeMetrics().distances;
      const std::optional<rl::AttemptSchedule::Slot> slot = schedule.Next(solved);
      if (!slot) break;
      const int entity = slot->entity;
      if (entity >= layout.num_entities) continue;
      EvalEpisodeObserver::Attempt record;
      record.index = index++;
      record.entity = entity;
      record.distance_before = before_attempt[entity];
      record.skipped = slot->skipped;
      if (!record.skipped) {
        const env::Vec2& g = env.goals()[entity];
        rl::WriteSubgoalToken(layout.num_kinds, env.layout().kinds[entity], static_cast<float>(g[0]),
                              static_cast<float>(g[1]), goal.data());
        if (!attempt(goal, entity, options.attempt_steps)) return std::nullopt;
      }
      const std::vector<double> after_attempt = record.skipped ? before_attempt : env.ComputeMetrics().distances;
      record.distance_after = after_attempt[entity];
      record.distances_before = before_attempt;
      record.distances_after = after_attempt;
      for (int other : subgoal_entities) {
        if (other == entity || other == 0 || other >= layout.num_entities || before_attempt[other] >= options.threshold)
          continue;
        const bool undone = after_attempt[other] >= options.threshold;
        ++record.others_solved;
        record.others_undone += undone ? 1 : 0;
        if ((structure.ancestor_mask[entity] >> other) & 1u) continue;
        ++record.independent_solved;
        record.independent_undone += undone ? 1 : 0;
      }
      if (!record.skipped) {  // a slot used up without steps undoes nothing: not counted
        independent_solved += record.independent_solved;
        independent_undone += record.independent_undone;
      }
      if (watcher) watcher->OnAttempt(record);
    }
  }
  const env::Metrics m = env.ComputeMetrics();
  rl::EpisodeMetrics out;
  out.entity_distance = m.distances;
  out.avg_distance = m.avg_distance;
  out.avg_object_distance = m.avg_object_distance;
  out.success = m.success;
  out.selectivity = selectivity_steps ? selectivity_sum / selectivity_steps : -1.0;
  out.independent_solved = independent_solved;
  out.independent_undone = independent_undone;
  return out;
}

rl::EvaluationSummary EvaluatePolicy(env::Environment& env, rl::PolicyNetwork<float>* policy,
                                     const rl::CatalogueSubgoals& subgoals, const EvalOptions& options, int episodes,
                                     uint64_t run_seed, uint64_t* unstable, rl::PolicyNetwork<float>* high_policy,
                                     EvalRecorder* recorder, uint64_t policy_version) {
  rl::EvaluationSummary summary;
  for (int i = 0; i < episodes; ++i) {
    const uint64_t seed = rl::EvalEpisodeSeed(run_seed, i);
    EvalEpisodeObserver* observer = recorder ? recorder->Begin(policy_version, i, seed) : nullptr;
    const auto metrics = RunEvaluationEpisode(env, policy, subgoals, options, seed, high_policy, observer);
    if (observer) recorder->End(metrics, env.steps());
    if (metrics)
      summary.Add(*metrics, options.threshold);
    else
      ++*unstable;
  }
  return summary;
}

}  // namespace srics::actor
