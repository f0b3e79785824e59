#include "common/rl/updates.h"

#include <cmath>

#include "common/rl/episode.h"

namespace srics::rl {

std::string ParameterProblem(const std::vector<float>& parameters) {
  if (AllFiniteWithin(parameters.data(), parameters.size(), kMaxAbsParameter)) return "";
  for (size_t i = 0; i < parameters.size(); ++i) {
    const float v = parameters[i];
    if (!std::isfinite(v)) return "parameter " + std::to_string(i) + " is not finite";
    if (std::fabs(v) > kMaxAbsParameter)
      return "parameter " + std::to_string(i) + " = " + std::to_string(v) + " outside +-" +
             std::to_string(kMaxAbsParameter);
  }
  return "";
}

const char* NodePhaseName(NodePhase phase) {
  switch (phase) {
    case NodePhase::kStarting: return "starting";
    case NodePhase::kWaiting: return "waiting";
    case NodePhase::kExploring: return "exploring";
    case NodePhase::kTraining: return "training";
    case NodePhase::kEvaluating: return "evaluating";
    case NodePhase::kStopping: return "stopping";
    case NodePhase::kFailed: return "failed";
  }
  return "invalid";
}

std::string ImplausibleProgress(const LearnerProgress& p, uint64_t budget_env_steps) {
  if (p.budget_env_steps != budget_env_steps)
    return "budget of " + std::to_string(p.budget_env_steps) + " env steps, this run's is " +
           std::to_string(budget_env_steps);
  // the episode that reaches the budget is stored whole: at most one episode beyond it
  if (budget_env_steps > 0 && p.training_env_steps > budget_env_steps + kMaxEpisodeSteps)
    return "training_env_steps " + std::to_string(p.training_env_steps) + " beyond the budget " +
           std::to_string(budget_env_steps) + " and one episode";
  if (p.training_env_steps > p.transitions_inserted)
    return "training_env_steps " + std::to_string(p.training_env_steps) + " above transitions_inserted " +
           std::to_string(p.transitions_inserted);
  if (p.replay_size > p.transitions_inserted)
    return "replay_size " + std::to_string(p.replay_size) + " above transitions_inserted " +
           std::to_string(p.transitions_inserted);
  // the backlog is at most what every inserted transition could owe at the largest ratio a
  // config accepts, and never far below zero (the learner runs ahead by its error buffer only)
  if (!std::isfinite(p.update_backlog) || std::abs(p.update_backlog) > 1e15)
    return "update_backlog " + std::to_string(p.update_backlog) + " not a plausible count of updates";
  return "";
}

}  // namespace srics::rl
