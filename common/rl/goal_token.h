#pragma once
// The goal token the attention networks take as query:
//   subgoal: [one-hot kind of the subgoal entity (K), goal x, goal y, 1]   (K + 3 floats)
//   full goal (SAC+HER): [x_0, y_0, ..., x_{N-1}, y_{N-1}]                  (2N floats)
// Networks that take several goal tokens (graph.object_ties: joint) get one subgoal token per
// member of the subgoal side by side, zero tokens after (their constant 1 is 0: padding).
// One definition for actors (single observations) and the learner (batches).

#include <algorithm>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

#include "common/rl/graph.h"

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

// Writes `tokens` subgoal tokens into out[0 .. tokens * (K+3)): member k of `subgoal` (kind
// kinds[member], goal goal[2k], goal[2k + 1]) in token k, zeros after. tokens >= subgoal.size().
inline void WriteSubgoalTokens(int num_kinds, int tokens, const SubgoalUnit& subgoal, std::span<const uint16_t> kinds,
                               const float* goal, float* out) {
  if (subgoal.size() > tokens)
    throw std::invalid_argument("a subgoal of " + std::to_string(subgoal.size()) + " entities for networks taking " +
                                std::to_string(tokens) + " goal token(s)");
  const int size = SubgoalTokenSize(num_kinds);
  std::fill(out, out + tokens * size, 0.0f);
  for (int k = 0; k < subgoal.size(); ++k)
    WriteSubgoalToken(num_kinds, kinds[subgoal.member(k)], goal[2 * k], goal[2 * k + 1], out + k * size);
}

}  // namespace srics::rl
