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

// The parameters are converted apart (moved where they can be).
template <typename Op, typename M, typename R>
void WeightsFields(const Op& op, M& m, R& w) {
  SRICS_FIELDS(op, m, w, version, update_count, architecture);
}

// The structure is converted apart (recomputed from the adjacency on the way in).
template <typename Op, typename M, typename R>
void GraphFields(const Op& op, M& m, R& g) {
  SRICS_FIELDS(op, m, g, version, mean_weights, threshold, held_out_loss, training_updates, episodes_used);
  SRICS_FIELDS(op, m, g.graph, num_entities, adjacency, action_entity);
}

template <typename Op, typename M, typename R>
void NodeFields(const Op& op, M& m, R& r) {
  SRICS_FIELDS(op, m, r, policy_version, graph_version);
  op(m.env_steps, r.steps, "steps");
  op(m.dropped_samples, r.dropped, "dropped");
}

}  // namespace

PolicyWeights ToMessage(const rl::WeightsUpdate& w) {
  PolicyWeights m;
  WeightsFields(ToMessageOp{}, m, w);
  m.parameters = w.parameters;
  return m;
}

PolicyWeights ToMessage(rl::WeightsUpdate&& w) {
  PolicyWeights m;
  WeightsFields(ToMessageOp{}, m, w);
  m.parameters = std::move(w.parameters);  // megabytes: moved, not copied
  return m;
}

rl::WeightsUpdate FromMessage(PolicyWeights m) {
  rl::WeightsUpdate w;
  WeightsFields(FromMessageOp{}, m, w);
  w.parameters = std::move(m.parameters);  // megabytes: moved, not copied
  return w;
}

InteractionGraph ToMessage(const rl::GraphUpdate& g) {
  InteractionGraph m;
  GraphFields(ToMessageOp{}, m, g);
  m.ancestor_masks = g.structure.ancestor_mask;
  m.depths.assign(g.structure.depth.begin(), g.structure.depth.end());
  return m;
}

rl::GraphUpdate FromMessage(const InteractionGraph& m) {
  rl::GraphUpdate g;
  GraphFields(FromMessageOp{}, m, g);
  const std::string problem = rl::ValidateGraph(g.graph);
  if (!problem.empty()) throw std::invalid_argument("interaction graph: " + problem);
  g.structure = rl::ComputeSubgoalStructure(g.graph);
  if (m.ancestor_masks != g.structure.ancestor_mask)
    throw std::invalid_argument("interaction graph: ancestor sets disagree with the adjacency");
  if (!std::equal(m.depths.begin(), m.depths.end(), g.structure.depth.begin(), g.structure.depth.end()))
    throw std::invalid_argument("interaction graph: depths disagree with the adjacency");
  return g;
}

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
