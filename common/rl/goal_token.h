#pragma once
// The goal token the attention networks take as query:
//   subgoal: [one-hot kind of the subgoal entity (K), goal x, goal y, 1]   (K + 3 floats)
//   full goal (SAC+HER): [x_0, y_0, ..., x_{N-1}, y_{N-1}]                  (2N floats)
// One definition for actors (single observations) and the learner (batches).

#include <algorithm>

namespace srics::rl {

inline int SubgoalTokenSize(int num_kinds) { return num_kinds + 3; }

// Writes a subgoal token into out[0 .. K+3).
inline void WriteSubgoalToken(int num_kinds, int kind, float goal_x, float goal_y, float* out) {
  std::fill(out, out + num_kinds + 3, 0.0f);
  out[kind] = 1.0f;
  out[num_kinds] = goal_x;
  out[num_kinds + 1] = goal_y;
  out[num_kinds + 2] = 1.0f;
}

}  // namespace srics::rl
