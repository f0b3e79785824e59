#pragma once
// One whole episode as the algorithms see it: what actors produce, the learner stores and
// the graph service learns from. Plain data; transport converts it to and from the wire.

#include <cstdint>
#include <string>
#include <vector>

#include "common/rl/entity_layout.h"

namespace srics::rl {

enum class EpisodeMode { kExplore, kTrain, kEval };

struct Episode {
  EntityLayout layout;
  std::vector<uint16_t> entity_kinds;  // N identifiers (0 = arm)
  int num_steps = 0;                   // T
  int action_dim = 2;                  // A
  std::vector<float> states;           // (T + 1) x N x D
  std::vector<float> actions;          // T x A
  int subgoal_entity = -1;             // -1: no subgoal (explore) or the full goal
  std::vector<float> goal;             // 2 (subgoal), 2N (full goal) or empty
  uint64_t ancestor_mask = 0;
  EpisodeMode mode = EpisodeMode::kExplore;
  uint32_t actor_id = 0;
  uint64_t episode_id = 0;
  uint64_t policy_version = 0;
  uint64_t graph_version = 0;

  const float* state(int t) const { return states.data() + static_cast<size_t>(t) * layout.state_size(); }
  const float* action(int t) const { return actions.data() + static_cast<size_t>(t) * action_dim; }
};

// Empty when the episode is internally consistent (sizes match the layout, values finite,
// the subgoal entity exists); otherwise what is wrong. The learner and the graph service
// call it on everything that came from the network.
std::string ValidateEpisode(const Episode& episode);

}  // namespace srics::rl
