#pragma once
// The rewards of the methods (docs/method.md section 3), for one transition. All read
// positions through an EntityLayout; `goal` is an xy pair (subgoal) or 2N floats (full goal).

#include <cstdint>
#include <optional>

#include "common/config/agent_config.h"
#include "common/rl/entity_layout.h"

namespace srics::rl {

// SRICS: distance of the subgoal entity plus the selectivity term, minus disturbance_weight
// times the summed motion of the entities outside {entity} and its ancestors. `ancestors` is
// the ancestor mask of `entity` (bit j set: j in P^entity). The form (paper / reference code)
// and the constants come from `config`.
double SelectivityReward(const EntityLayout& layout, const float* before, const float* after, int entity,
                         const float* goal, uint64_t ancestors, const config::RewardConfig& config);

// SMORL and the no-selectivity ablation: r = -||s_k - g_k||.
double DistanceReward(const EntityLayout& layout, const float* after, int entity, const float* goal);

// SAC+HER: r = -||s - g|| over the xy of every entity (goal holds 2N floats).
double FullGoalReward(const EntityLayout& layout, const float* after, const float* goal);

// The selectivity measure as a metric, in [0, 1]: the share of the motion of everything that
// is neither the subgoal entity nor one of its ancestors which belongs to the subgoal entity,
// ||Δs_k|| / (||Δs_k|| + mean_j ||Δs_j||). Empty when nothing moved (sum below epsilon).
std::optional<double> SelectivityMeasure(const EntityLayout& layout, const float* before, const float* after,
                                         int entity, uint64_t ancestors, double epsilon);

}  // namespace srics::rl
