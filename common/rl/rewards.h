#pragma once
// The rewards of the methods (docs/method.md section 3), for one transition. All read
// positions through an EntityLayout; `goal` is an xy pair (subgoal) or 2N floats (full goal).

#include <cstdint>
#include <optional>

#include "common/config/agent_config.h"
#include "common/rl/entity_layout.h"
#include "common/rl/graph.h"

namespace srics::rl {

// The subgoal is a unit (common/rl/graph.h): one entity, or a tied pair attempted as one, whose
// goal holds 2 floats per member (entity, then partner). For a pair, its distance is the sum of
// the members', it is solved when each member is within the threshold, its own motion is the
// sum of the members', and the others are the entities outside the pair and its ancestors.

// The subgoal's distance to its goal in `state`: summed over its members (the reward's) and the
// farthest member's (solved when below the threshold).
struct SubgoalDistance {
  double sum = 0;
  double max = 0;
};
SubgoalDistance DistanceToSubgoal(const EntityLayout& layout, const float* state, const SubgoalUnit& subgoal,
                                  const float* goal);

// SRICS: distance of the subgoal plus the selectivity term, minus disturbance_weight times the
// summed motion of the entities outside the subgoal and its ancestors. `ancestors` is the
// subgoal's ancestor mask (bit j set: j in P^i; SubgoalStructure::AncestorsOf for a pair). The
// form (paper / reference code) and the constants come from `config`.
double SelectivityReward(const EntityLayout& layout, const float* before, const float* after,
                         const SubgoalUnit& subgoal, const float* goal, uint64_t ancestors,
                         const config::RewardConfig& config);

// SMORL and the no-selectivity ablation: r = -||s_k - g_k|| (a pair: the sum of both).
double DistanceReward(const EntityLayout& layout, const float* after, const SubgoalUnit& subgoal, const float* goal);

// SAC+HER: r = -||s - g|| over the xy of every entity (goal holds 2N floats).
double FullGoalReward(const EntityLayout& layout, const float* after, const float* goal);

// The selectivity measure as a metric, in [0, 1]: the share of the motion of everything that
// is neither the subgoal (its entity or pair) nor one of its ancestors which belongs to the
// subgoal, ||Δs_k|| / (||Δs_k|| + mean_j ||Δs_j||). Empty when nothing moved (sum below epsilon).
std::optional<double> SelectivityMeasure(const EntityLayout& layout, const float* before, const float* after,
                                         const SubgoalUnit& subgoal, uint64_t ancestors, double epsilon);

}  // namespace srics::rl
