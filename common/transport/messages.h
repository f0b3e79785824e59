#pragma once
// Plain C++ mirrors of the IDL types in idl/srics.idl, one struct per topic but Episode
// (rl::Episode, common/rl/episode.h, is the only episode shape). Algorithms and
// process code use these; only common/transport converts them to and from the generated C
// types, so this header has no DDS dependency. Field meanings and units: idl/README.md.

#include <cstdint>
#include <string>
#include <vector>

#include "common/transport/wire.h"

namespace srics::transport {

// The enum carries the raw wire value, so a received out-of-range value stays representable
// and validation (not a cast) rejects it. (Episodes have no struct here: the wire type converts
// straight to and from rl::Episode, whose EpisodeMode carries the wire values.)
enum class NodeState : int32_t {
  kStarting = 0,
  kWaiting = 1,
  kExploring = 2,
  kTraining = 3,
  kEvaluating = 4,
  kStopping = 5,
  kFailed = 6,
};

// Lowercase names ("starting", "training", ...) for logs; "invalid" for out-of-range values.
const char* NodeStateName(NodeState state);

// Health of one process (topic "srics/node_status"), keyed by run, role and id.
struct NodeStatus {
  uint32_t contract_version = kContractVersion;
  std::string run_id;
  std::string role;  // actor, learner, graph, monitor, launcher
  uint32_t node_id = 0;
  std::string host;
  int32_t pid = 0;
  NodeState state = NodeState::kStarting;
  uint64_t policy_version = 0;
  uint64_t graph_version = 0;
  uint64_t env_steps = 0;
  uint64_t dropped_samples = 0;  // malformed samples rejected by this node
  uint64_t uptime_ms = 0;
  std::string detail;

  bool operator==(const NodeStatus&) const = default;
};

}  // namespace srics::transport
