#include "actor/hac_acting.h"

#include "actor/episode_parts.h"

namespace srics::actor {

bool HacActor::SubgoalOver(const nn::Tensor& entities) const {
  return held_ < 0 || held_ >= options_.horizon ||
         rl::GoalReached(layout_, entities.data(), subgoal_.data(), options_.threshold) ||
         rl::GoalReached(layout_, entities.data(), full_goal_.data(), options_.threshold);
}

const std::vector<float>& HacActor::Propose(const nn::Tensor& entities, bool deterministic, bool test, nn::Rng& rng) {
  const nn::Tensor& action = high_.Act(entities, full_goal_, deterministic, rng);
  rl::SubgoalFromAction(options_.box, action.data(), layout_.num_entities, subgoal_.data());
  WriteGoalToken(subgoal_.data(), layout_.num_entities, &subgoal_token_, static_cast<int>(full_goal_.cols()));
  held_ = 0;
  test_ = test;
  return subgoal_;
}

const nn::Tensor& HacActor::Act(const nn::Tensor& entities, bool deterministic, nn::Rng& rng) {
  ++held_;
  return low_.Act(entities, subgoal_token_, deterministic || test_, rng);
}

}  // namespace srics::actor
