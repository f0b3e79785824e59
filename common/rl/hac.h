#pragma once
// What actors and the learner agree on for the HAC baseline (Levy et al. 2019, two levels;
// docs/method.md section 3). The high level's action is a subgoal, the xy of every entity,
// mapped affinely from [-1, 1] onto the table inside its walls. Goals of both levels hold 2
// floats per entity (the low level's is a subgoal, the high level's the full goal); a goal is
// reached when every entity is within the threshold of its goal xy.

#include <vector>

#include "common/config/env_config.h"
#include "common/rl/entity_layout.h"
#include "common/rl/episode.h"

namespace srics::rl {

// The region subgoals are proposed in: the table inside its walls (where every entity is).
struct SubgoalBox {
  float x_min = -0.25f, x_max = 0.25f, y_min = 0.35f, y_max = 0.76f;
};
SubgoalBox SubgoalBoxFor(const config::EnvConfig& env);

// The subgoal (2N floats) a high-level action in [-1, 1] (at least 2N values) proposes.
void SubgoalFromAction(const SubgoalBox& box, const float* action, int num_entities, float* subgoal);
// The high-level action proposing `subgoal` (2N floats), clipped to [-1, 1].
void ActionFromSubgoal(const SubgoalBox& box, const float* subgoal, int num_entities, float* action);

// The xy of every entity of a state (2N floats).
void AchievedGoal(const EntityLayout& layout, const float* state, float* out);
// True when every entity's xy is within `threshold` (Euclidean) of its goal xy (2N floats).
bool GoalReached(const EntityLayout& layout, const float* state, const float* goal, double threshold);

// One high-level step of an episode: steps [start, end) under subgoal `index` (-1: none).
struct HacSegment {
  int start = 0;
  int end = 0;
  int index = -1;
  bool operator==(const HacSegment&) const = default;
};
// The high-level steps of an episode: the subgoals the actor recorded, or for an episode with
// none (exploration), consecutive chunks of `horizon` steps without a proposed subgoal.
std::vector<HacSegment> HacSegments(const Episode& episode, int horizon);

}  // namespace srics::rl
