#include "actor/episode_parts.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "common/profile/phase_clock.h"

namespace srics::actor {

rl::EntityLayout LayoutOf(const env::Environment& env) {
  const env::EntityLayout& l = env.layout();
  return {l.num_entities, l.num_kinds, l.velocities};
}

const nn::Tensor& Observer::Observe(const env::Environment& env) {
  env.GetStates(&buffer_);
  entities_.resize(layout_.num_entities, layout_.entity_dim());
  for (size_t i = 0; i < buffer_.size(); ++i) entities_.data()[i] = static_cast<float>(buffer_[i]);
  return entities_;
}

rl::Episode StartEpisode(const env::Environment& env, const rl::EntityLayout& layout) {
  rl::Episode episode;
  episode.layout = layout;
  for (int kind : env.layout().kinds) episode.entity_kinds.push_back(static_cast<uint16_t>(kind));
  episode.action_dim = env.action_dim();
  return episode;
}

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

void WriteGoalToken(const float* xy, int num_entities, nn::Tensor* token, int goal_dim) {
  token->setZero(1, goal_dim);
  std::copy(xy, xy + 2 * num_entities, token->data());
}

nn::Tensor PaddedFullGoalToken(const env::Environment& env, int goal_dim) {
  const nn::Tensor goal = FullGoalToken(env);
  nn::Tensor token;
  WriteGoalToken(goal.data(), static_cast<int>(goal.cols() / 2), &token, goal_dim);
  return token;
}

}  // namespace srics::actor
