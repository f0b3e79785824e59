#include "common/rl/hac.h"

#include <algorithm>

namespace srics::rl {

SubgoalBox SubgoalBoxFor(const config::EnvConfig& env) {
  SubgoalBox box;
  box.x_min = static_cast<float>(-env.table.wall_x);
  box.x_max = static_cast<float>(env.table.wall_x);
  box.y_min = static_cast<float>(env.table.wall_y_low);
  box.y_max = static_cast<float>(env.table.wall_y_high);
  return box;
}

void SubgoalFromAction(const SubgoalBox& box, const float* action, int num_entities, float* subgoal) {
  const float cx = 0.5f * (box.x_min + box.x_max), hx = 0.5f * (box.x_max - box.x_min);
  const float cy = 0.5f * (box.y_min + box.y_max), hy = 0.5f * (box.y_max - box.y_min);
  for (int j = 0; j < num_entities; ++j) {
    subgoal[2 * j] = cx + hx * std::clamp(action[2 * j], -1.0f, 1.0f);
    subgoal[2 * j + 1] = cy + hy * std::clamp(action[2 * j + 1], -1.0f, 1.0f);
  }
}

void ActionFromSubgoal(const SubgoalBox& box, const float* subgoal, int num_entities, float* action) {
  const float cx = 0.5f * (box.x_min + box.x_max), hx = 0.5f * (box.x_max - box.x_min);
  const float cy = 0.5f * (box.y_min + box.y_max), hy = 0.5f * (box.y_max - box.y_min);
  for (int j = 0; j < num_entities; ++j) {
    action[2 * j] = std::clamp((subgoal[2 * j] - cx) / hx, -1.0f, 1.0f);
    action[2 * j + 1] = std::clamp((subgoal[2 * j + 1] - cy) / hy, -1.0f, 1.0f);
  }
}

void AchievedGoal(const EntityLayout& layout, const float* state, float* out) {
  for (int j = 0; j < layout.num_entities; ++j) {
    out[2 * j] = layout.x(state, j);
    out[2 * j + 1] = layout.y(state, j);
  }
}

bool GoalReached(const EntityLayout& layout, const float* state, const float* goal, double threshold) {
  for (int j = 0; j < layout.num_entities; ++j)
    if (!(DistanceToGoal(layout, state, j, goal + 2 * j) < threshold)) return false;
  return true;
}

std::vector<HacSegment> HacSegments(const Episode& e, int horizon) {
  std::vector<HacSegment> segments;
  if (e.num_subgoals() > 0) {
    for (int k = 0; k < e.num_subgoals(); ++k) segments.push_back({e.subgoal_start(k), e.subgoal_end(k), k});
    return segments;
  }
  for (int start = 0; start < e.num_steps; start += horizon)
    segments.push_back({start, std::min(start + horizon, e.num_steps), -1});
  return segments;
}

}  // namespace srics::rl
