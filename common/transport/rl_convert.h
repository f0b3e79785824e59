#pragma once
// Conversions between the wire messages (messages.h) and the algorithms' plain types
// (common/rl). Messages reaching these functions were validated by the Reader (sizes,
// finiteness); what the wire cannot say (whether states carry velocities) comes from config.

#include <string>
#include <vector>

#include "common/rl/episode.h"
#include "common/rl/graph.h"
#include "common/transport/messages.h"

namespace srics::transport {

Episode ToMessage(const rl::Episode& episode);

// Throws std::invalid_argument when the message does not fit the layout (entity_dim too
// small for the velocity flag).
rl::Episode FromMessage(const Episode& message, bool velocities);

// A graph as the algorithms use it.
struct ReceivedGraph {
  uint64_t version = 0;
  rl::InteractionGraph graph;
  rl::SubgoalStructure structure;  // recomputed from the adjacency, never trusted from the wire
  std::vector<float> mean_weights;
  float held_out_loss = 0;
};

InteractionGraph ToMessage(const rl::InteractionGraph& graph, const rl::SubgoalStructure& structure,
                           const std::vector<double>& mean_weights, float threshold, uint64_t version,
                           float held_out_loss, uint64_t training_updates, uint32_t episodes_used);

// Rebuilds the graph and recomputes ancestor sets and depths; throws std::invalid_argument
// when the message's own ancestor masks or depths disagree with its adjacency (a peer with a
// different algorithm or a corrupted sample).
ReceivedGraph FromMessage(const InteractionGraph& message);

}  // namespace srics::transport
