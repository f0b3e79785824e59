#include "actor/episode_options.h"

namespace srics::actor {

HacActOptions HacActOptionsFor(const config::Config& config, const rl::RunShape& shape) {
  HacActOptions hac;
  hac.horizon = config.agent.hac.horizon;
  hac.test_probability = config.agent.hac.subgoal_test_probability;
  hac.threshold = config.agent.hac.goal_threshold;
  hac.box = shape.subgoal_box;
  return hac;
}

TrainOptions TrainOptionsFor(const config::Config& config, const rl::RunShape& shape) {
  TrainOptions train;
  train.steps = config.actors.train_episode_steps;
  train.full_goal = config.run.method == config::Method::kSacHer;
  train.sampling = config.env.sampling;
  train.chain_episodes = config.actors.train_chain_episodes;
  if (config.run.method == config::Method::kHac) {
    train.hac = HacActOptionsFor(config, shape);
    train.steps = train.hac->horizon * train.hac->horizon;
  }
  return train;
}

EvalOptions EvalOptionsFor(const config::Config& config, const rl::RunShape& shape) {
  const config::Method method = config.run.method;
  EvalOptions eval;
  eval.attempt_steps = config.actors.eval_attempt_steps;
  eval.protocol = config.actors.eval_schedule == config::EvalSchedule::kReference
                      ? rl::EvaluationProtocol::kReference
                      : rl::EvaluationProtocol::kIndependentDraws;
  eval.full_goal = method == config::Method::kSacHer || method == config::Method::kHac;
  if (method == config::Method::kHac) eval.hac = HacActOptionsFor(config, shape);
  eval.threshold = config.env.success_threshold;
  eval.epsilon = config.agent.reward.epsilon;
  eval.order = (method == config::Method::kSrics || method == config::Method::kSricsNoSelectivity)
                   ? rl::SubgoalOrder::kDepth
                   : rl::SubgoalOrder::kRandom;
  return eval;
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

}  // namespace srics::actor
