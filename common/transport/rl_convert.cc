#include "common/transport/rl_convert.h"

#include <algorithm>
#include <stdexcept>

#include "common/transport/field_list.h"

namespace srics::transport {

namespace {

// op(message field, rl field, name): the lists below serve both directions.
struct ToMessageOp {
  template <typename M, typename R>
  void operator()(M& message, const R& value, const char*) const {
    if constexpr (requires { message.assign(value.begin(), value.end()); })
      message.assign(value.begin(), value.end());  // vectors of another element type
    else
      message = static_cast<M>(value);
  }
};

struct FromMessageOp {
  template <typename M, typename R>
  void operator()(const M& message, R& value, const char*) const {
    if constexpr (requires { value.assign(message.begin(), message.end()); })
      value.assign(message.begin(), message.end());
    else
      value = static_cast<R>(message);
  }
};

template <typename Op, typename M, typename R>
void NodeFields(const Op& op, M& m, R& r) {
  SRICS_FIELDS(op, m, r, policy_version, graph_version);
  op(m.env_steps, r.steps, "steps");
  op(m.dropped_samples, r.dropped, "dropped");
}

}  // namespace

NodeStatus ToMessage(const rl::NodeReport& r, const std::string& role, uint32_t node_id) {
  NodeStatus m;
  NodeFields(ToMessageOp{}, m, r);
  m.role = role;
  m.node_id = node_id;
  m.state = ToNodeState(r.phase);
  m.detail = r.detail.substr(0, kDetailMaxLength);
  return m;
}

rl::NodeReport FromMessage(const NodeStatus& m) {
  rl::NodeReport r;
  NodeFields(FromMessageOp{}, m, r);
  r.phase = ToNodePhase(m.state);
  r.detail = m.detail;
  return r;
}

NodeState ToNodeState(rl::NodePhase phase) {
  switch (phase) {
    case rl::NodePhase::kStarting: return NodeState::kStarting;
    case rl::NodePhase::kWaiting: return NodeState::kWaiting;
    case rl::NodePhase::kExploring: return NodeState::kExploring;
    case rl::NodePhase::kTraining: return NodeState::kTraining;
    case rl::NodePhase::kEvaluating: return NodeState::kEvaluating;
    case rl::NodePhase::kStopping: return NodeState::kStopping;
    case rl::NodePhase::kFailed: return NodeState::kFailed;
  }
  return NodeState::kFailed;
}

rl::NodePhase ToNodePhase(NodeState state) {
  for (rl::NodePhase phase : {rl::NodePhase::kStarting, rl::NodePhase::kWaiting, rl::NodePhase::kExploring,
                              rl::NodePhase::kTraining, rl::NodePhase::kEvaluating, rl::NodePhase::kStopping})
    if (ToNodeState(phase) == state) return phase;
  return rl::NodePhase::kFailed;
}

}  // namespace srics::transport
