#pragma once
// Attention network shapes shared by the network tests and the nn bench.

#include "common/rl/networks.h"

namespace srics::rl::testing {

// A tiny network for gradient checks: every size differs, so a transposed shape shows.
inline AttentionNetworkConfig SmallNetworkConfig() {
  return {.entity_dim = 5,
          .goal_dim = 6,
          .action_dim = 2,
          .embed_dim = 8,
          .num_heads = 2,
          .policy_hidden = {7, 6},
          .q_hidden = {6, 5, 4}};
}

// The paper's network for `entities` entities: entity token [one-hot id (K = entities), x, y],
// goal token [one-hot, goal xy, 1].
inline AttentionNetworkConfig PaperNetworkConfig(int entities) {
  return {.entity_dim = entities + 2,
          .goal_dim = entities + 3,
          .action_dim = 2,
          .embed_dim = 80,
          .num_heads = 5,
          .policy_hidden = {128, 128},
          .q_hidden = {128, 128, 128}};
}

}  // namespace srics::rl::testing
