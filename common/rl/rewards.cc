#include "common/rl/rewards.h"

#include <algorithm>
#include <cmath>

namespace srics::rl {
namespace {

// Sum and count of ||Δs_j|| over entities that are neither in the subgoal nor its ancestors.
struct IndependentMotion {
  double sum = 0;
  int count = 0;
  double mean() const { return count ? sum / count : 0.0; }
};

IndependentMotion MotionOfOthers(const EntityLayout& layout, const float* before, const float* after,
                                 const SubgoalUnit& subgoal, uint64_t ancestors) {
  IndependentMotion motion;
  for (int j = 0; j < layout.num_entities; ++j) {
    if (subgoal.contains(j) || ((ancestors >> j) & 1u)) continue;
    motion.sum += Displacement(layout, before, after, j);
    ++motion.count;
  }
  return motion;
}

// Summed over the subgoal's members.
double OwnMotion(const EntityLayout& layout, const float* before, const float* after, const SubgoalUnit& subgoal) {
  double motion = 0;
  for (int k = 0; k < subgoal.size(); ++k) motion += Displacement(layout, before, after, subgoal.member(k));
  return motion;
}

}  // namespace

namespace {

// The selectivity reward of the configured form, without the disturbance term.
double FormReward(const SubgoalDistance& goal, double own_motion, const IndependentMotion& others,
                  const config::RewardConfig& config) {
  const double distance = goal.sum;
  const bool solved = goal.max < config.solved_threshold;
  if (config.selectivity_form == config::SelectivityForm::kReference) {
    // reference code: mean motion of the independent entities; sel in [-1, 0]
    if (solved) return -distance - others.mean();
    const double total = own_motion + others.mean();
    const double selectivity = total > config.epsilon ? -1.0 + own_motion / total : -1.0;
    return -distance + config.selectivity_weight * selectivity;
  }
  // paper: sums over j not in P^i (the entity itself included in the denominator)
  double selectivity;
  if (solved) {
    selectivity = 1.0 - others.sum;
  } else {
    const double total = own_motion + others.sum;
    selectivity = total > config.epsilon ? own_motion / total : 0.0;
  }
  return -distance + config.selectivity_weight * (selectivity - 1.0);
}

}  // namespace

double SelectivityReward(const EntityLayout& layout, const float* before, const float* after,
                         const SubgoalUnit& subgoal, const float* goal, uint64_t ancestors,
                         const config::RewardConfig& config) {
  const double own_motion = OwnMotion(layout, before, after, subgoal);
  const IndependentMotion others = MotionOfOthers(layout, before, after, subgoal, ancestors);
  const double reward = FormReward(DistanceToSubgoal(layout, after, subgoal, goal), own_motion, others, config);
  // skipped at 0 so that runs without the term keep their rewards bit for bit
  return config.disturbance_weight > 0 ? reward - config.disturbance_weight * others.sum : reward;
}

double DistanceReward(const EntityLayout& layout, const float* after, const SubgoalUnit& subgoal, const float* goal) {
  return -DistanceToSubgoal(layout, after, subgoal, goal).sum;
}

SubgoalDistance DistanceToSubgoal(const EntityLayout& layout, const float* state, const SubgoalUnit& subgoal,
                                  const float* goal) {
  SubgoalDistance d;
  for (int k = 0; k < subgoal.size(); ++k) {
    const double member = DistanceToGoal(layout, state, subgoal.member(k), goal + 2 * k);
    d.sum += member;
    d.max = std::max(d.max, member);
  }
  return d;
}

double FullGoalReward(const EntityLayout& layout, const float* after, const float* goal) {
  double squared = 0;
  for (int j = 0; j < layout.num_entities; ++j) {
    const double dx = layout.x(after, j) - goal[2 * j];
    const double dy = layout.y(after, j) - goal[2 * j + 1];
    squared += dx * dx + dy * dy;
  }
  return -std::sqrt(squared);
}

std::optional<double> SelectivityMeasure(const EntityLayout& layout, const float* before, const float* after,
                                         const SubgoalUnit& subgoal, uint64_t ancestors, double epsilon) {
  const double own_motion = OwnMotion(layout, before, after, subgoal);
  const double total = own_motion + MotionOfOthers(layout, before, after, subgoal, ancestors).mean();
  if (total <= epsilon) return std::nullopt;
  return own_motion / total;
}

}  // namespace srics::rl
