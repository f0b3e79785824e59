#pragma once
// How an observation is laid out: a set of N entity vectors of D floats each,
//   [identifier one-hot (num_kinds), x, y (, vx, vy)],
// entity 0 being the arm. States are stored row-major as N x D floats.

#include <cmath>
#include <cstddef>

namespace srics::rl {

struct EntityLayout {
  int num_entities = 0;  // N: the arm plus the objects present
  int num_kinds = 0;     // K: length of the identifier one-hot
  bool velocities = false;

  int entity_dim() const { return num_kinds + (velocities ? 4 : 2); }
  int state_size() const { return num_entities * entity_dim(); }
  // offset of entity i's x inside a state
  int position_offset(int entity) const { return entity * entity_dim() + num_kinds; }

  float x(const float* state, int entity) const { return state[position_offset(entity)]; }
  float y(const float* state, int entity) const { return state[position_offset(entity) + 1]; }
  bool operator==(const EntityLayout&) const = default;
};

// Euclidean distance between entity i's xy in a state and a goal xy.
inline double DistanceToGoal(const EntityLayout& layout, const float* state, int entity, const float* goal_xy) {
  const double dx = layout.x(state, entity) - goal_xy[0];
  const double dy = layout.y(state, entity) - goal_xy[1];
  return std::sqrt(dx * dx + dy * dy);
}

// How far entity i moved between two states (xy only).
inline double Displacement(const EntityLayout& layout, const float* before, const float* after, int entity) {
  const double dx = layout.x(after, entity) - layout.x(before, entity);
  const double dy = layout.y(after, entity) - layout.y(before, entity);
  return std::sqrt(dx * dx + dy * dy);
}

}  // namespace srics::rl
