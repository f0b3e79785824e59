#pragma once
// Conversions between the wire messages of messages.h and the algorithms' plain types
// (common/rl/updates.h). Episodes have no message struct: rl::Episode goes to and from the wire
// directly (convert.h). Messages reaching FromMessage were validated by the Reader (sizes,
// finiteness); the in-process run uses ToMessage to feed the monitor the same structs.

#include <cstdint>
#include <string>

#include "common/rl/updates.h"
#include "common/transport/messages.h"

namespace srics::transport {

// host, pid and uptime are the publishing process's (StatusPublisher fills them); the detail
// is cut to the IDL's bound.
NodeStatus ToMessage(const rl::NodeReport& report, const std::string& role, uint32_t node_id);
rl::NodeReport FromMessage(const NodeStatus& message);

NodeState ToNodeState(rl::NodePhase phase);
rl::NodePhase ToNodePhase(NodeState state);  // kFailed for an out-of-range state

}  // namespace srics::transport
