#include "common/transport/convert.h"

#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "common/transport/errors.h"
#include "common/transport/field_list.h"

namespace srics::transport {
namespace internal {

static_assert(srics_WIRE_CONTRACT_VERSION == kContractVersion,
              "kContractVersion (wire.h) must equal WIRE_CONTRACT_VERSION (idl/srics.idl)");
static_assert(srics_EPISODE_EXPLORE == static_cast<int>(rl::EpisodeMode::kExplore) &&
              srics_EPISODE_TRAIN == static_cast<int>(rl::EpisodeMode::kTrain) &&
              srics_EPISODE_EVAL == static_cast<int>(rl::EpisodeMode::kEval));
static_assert(srics_NODE_STARTING == static_cast<int>(rl::NodePhase::kStarting) &&
              srics_NODE_WAITING == static_cast<int>(rl::NodePhase::kWaiting) &&
              srics_NODE_EXPLORING == static_cast<int>(rl::NodePhase::kExploring) &&
              srics_NODE_TRAINING == static_cast<int>(rl::NodePhase::kTraining) &&
              srics_NODE_EVALUATING == static_cast<int>(rl::NodePhase::kEvaluating) &&
              srics_NODE_STOPPING == static_cast<int>(rl::NodePhase::kStopping) &&
              srics_NODE_FAILED == static_cast<int>(rl::NodePhase::kFailed));
// the IDL's counts are unsigned short and its ancestor masks 64-bit
static_assert(rl::kMaxEpisodeSteps <= std::numeric_limits<uint16_t>::max() && rl::kMaxEntities <= 64 &&
              rl::kMaxActionDim <= std::numeric_limits<uint16_t>::max());

namespace {

template <typename T>
using Mutable = std::remove_const_t<T>;

// A domain vector of V goes on the wire as it is when Element has its size and kind.
template <typename V, typename Element>
constexpr bool kSameLayout =
    sizeof(V) == sizeof(Element) && std::is_floating_point_v<V> == std::is_floating_point_v<Element>;

// Value -> C: strings copied into their bounded arrays, sequences borrowed (DDS only reads
// them while writing) or, of another element type, converted into `buffers`; scalars cast.
struct ToCOp {
  SequenceBuffers* buffers = nullptr;

  template <size_t N>
  void operator()(const std::string& in, char (&out)[N], const char* field) const {
    if (in.size() >= N)
      throw InvalidMessage(std::string(field) + ": " + std::to_string(in.size()) + " characters, the IDL allows " +
                           std::to_string(N - 1));
    std::memcpy(out, in.data(), in.size());
    out[in.size()] = '\0';
  }
  template <typename V, typename Seq>
  requires requires(Seq s) { s._buffer; }
  void operator()(const std::vector<V>& in, Seq& out, const char*) const {
    using Element = std::remove_pointer_t<decltype(out._buffer)>;
    if constexpr (kSameLayout<V, Element>) {
      out._buffer = reinterpret_cast<Element*>(const_cast<V*>(in.data()));
    } else {
      Element* converted = buffers->Hold<Element>(in.size());
      for (size_t i = 0; i < in.size(); ++i) converted[i] = static_cast<Element>(in[i]);
      out._buffer = converted;
    }
    out._length = out._maximum = static_cast<uint32_t>(in.size());
    out._release = false;
  }
  template <typename A, typename B>
  void operator()(const A& in, B& out, const char*) const {
    out = static_cast<B>(in);
  }
};

// C -> value: everything copied once, strings never read past their array.
struct FromCOp {
  template <size_t N>
  void operator()(std::string& out, const char (&in)[N], const char*) const {
    out.assign(in, strnlen(in, N));
  }
  template <typename V, typename Seq>
  requires requires(Seq s) { s._buffer; }
  void operator()(std::vector<V>& out, const Seq& in, const char*) const {
    using Element = std::remove_const_t<std::remove_pointer_t<decltype(in._buffer)>>;
    if (in._length == 0 || in._buffer == nullptr) {
      out.clear();
      return;
    }
    if constexpr (kSameLayout<V, Element>) {
      const auto* first = reinterpret_cast<const V*>(in._buffer);
      out.assign(first, first + in._length);
    } else {
      out.assign(in._buffer, in._buffer + in._length);  // converted element by element
    }
  }
  template <typename A, typename B>
  void operator()(A& out, const B& in, const char*) const {
    out = static_cast<A>(in);
  }
};

// The envelope's fields are named alike in every C type.
template <typename C>
void StampEnvelope(const Envelope& envelope, C* out) {
  const ToCOp op;
  op(envelope.contract_version, out->contract_version, "contract_version");
  op(envelope.run_id, out->run_id, "run_id");
}

// Each type's fields, used in both directions: op(message field, C field, name). M and C carry
// the constness of the direction (const M for ToC, const C for FromC).
template <typename C, typename Wanted>
concept Is = std::is_same_v<Mutable<C>, Wanted>;

template <typename Op, typename M, Is<srics_Episode> C>
void Fields(const Op& op, M& m, C& c) {
  // the envelope and entity_dim are not rl::Episode fields: ToC and FromC handle them
  SRICS_FIELDS(op, m, c, actor_id, episode_id, mode, policy_version, graph_version, action_dim, num_steps, entity_kinds,
               states, actions, subgoal_entity, goal, ancestor_mask, subgoal_starts, subgoals, subgoal_tests);
  op(m.layout.num_entities, c.num_entities, "num_entities");
}

template <typename Op, typename M, Is<srics_PolicyWeights> C>
void Fields(const Op& op, M& m, C& c) {
  SRICS_FIELDS(op, m, c, version, update_count, architecture, parameters);
}

template <typename Op, typename M, Is<srics_InteractionGraph> C>
void Fields(const Op& op, M& m, C& c) {
  SRICS_FIELDS(op, m, c, version, mean_weights, threshold, held_out_loss, training_updates, episodes_used);
  SRICS_FIELDS(op, m.graph, c, num_entities, adjacency, action_entity);
  op(m.structure.ancestor_mask, c.ancestor_masks, "ancestor_masks");
  op(m.structure.depth, c.depths, "depths");
}

// selectivity apart: the wire has no count of the episodes that defined it
template <typename Op, typename M, Is<srics_EvalResult> C>
void Fields(const Op& op, M& m, C& c) {
  SRICS_FIELDS(op, m, c, actor_id, policy_version, graph_version, env_steps);
  SRICS_FIELDS(op, m.summary, c, episodes, avg_distance, avg_object_distance, success_rate, entity_distance,
               subgoal_success, independent_solved, independent_undone);
}

template <typename Op, typename M, Is<srics_LearnerStats> C>
void Fields(const Op& op, M& m, C& c) {
  SRICS_FIELDS(op, m, c, updates, transitions_inserted, training_env_steps, budget_env_steps, replay_size,
               update_backlog, episodes_accepted, episodes_rejected, policy_version, q_loss, policy_loss, alpha,
               entropy, updates_per_second, inserts_per_second, mean_reward);
}

template <typename Op, typename M, Is<srics_NodeStatus> C>
void Fields(const Op& op, M& m, C& c) {
  SRICS_FIELDS(op, m, c, role, node_id, host, pid, uptime_ms);
  SRICS_FIELDS(op, m.report, c, policy_version, graph_version, detail);
  op(m.report.phase, c.state, "state");
  op(m.report.steps, c.env_steps, "env_steps");
  op(m.report.dropped, c.dropped_samples, "dropped_samples");
}

// The part of entity_dim after the identifier one-hot: x, y (, vx, vy).
int PerEntityExtra(bool velocities) { return velocities ? 4 : 2; }

}  // namespace

void ToC(const rl::Episode& in, const Envelope& envelope, srics_Episode* out) {
  std::memset(out, 0, sizeof(*out));
  const ToCOp op;
  Fields(op, in, *out);
  StampEnvelope(envelope, out);
  op(in.layout.entity_dim(), out->entity_dim, "entity_dim");
}

void FromC(const srics_Episode& in, bool velocities, rl::Episode* out) {
  Fields(FromCOp{}, *out, in);
  // a num_kinds below 1 is left for rl::ValidateEpisode to refuse
  out->layout.num_kinds = static_cast<int>(in.entity_dim) - PerEntityExtra(velocities);
  out->layout.velocities = velocities;
}

namespace {

// The fields every domain type shares with its C type, and the envelope.
template <typename T>
void ToCWithEnvelope(const T& in, const Envelope& envelope, typename CType<T>::type* out, SequenceBuffers* buffers) {
  std::memset(out, 0, sizeof(*out));
  buffers->clear();
  Fields(ToCOp{buffers}, in, *out);
  StampEnvelope(envelope, out);
}

}  // namespace

void ToC(const rl::LearnerReport& in, const Envelope& envelope, srics_LearnerStats* out, SequenceBuffers* buffers) {
  ToCWithEnvelope(in, envelope, out, buffers);
}

void FromC(const srics_LearnerStats& in, rl::LearnerReport* out) { Fields(FromCOp{}, *out, in); }

void ToC(const rl::EvalReport& in, const Envelope& envelope, srics_EvalResult* out, SequenceBuffers* buffers) {
  ToCWithEnvelope(in, envelope, out, buffers);
  out->selectivity = static_cast<float>(in.summary.selectivity_episodes ? in.summary.selectivity : 0.0);
}

void ToC(const rl::WeightsUpdate& in, const Envelope& envelope, srics_PolicyWeights* out, SequenceBuffers* buffers) {
  ToCWithEnvelope(in, envelope, out, buffers);
}

void FromC(const srics_PolicyWeights& in, rl::WeightsUpdate* out) { Fields(FromCOp{}, *out, in); }

void ToC(const rl::GraphUpdate& in, const Envelope& envelope, srics_InteractionGraph* out, SequenceBuffers* buffers) {
  ToCWithEnvelope(in, envelope, out, buffers);
}

void ToC(const rl::NodeStatus& in, const Envelope& envelope, srics_NodeStatus* out, SequenceBuffers* buffers) {
  ToCWithEnvelope(in, envelope, out, buffers);
}

void FromC(const srics_NodeStatus& in, rl::NodeStatus* out) {
  Fields(FromCOp{}, *out, in);
  out->report.rejections.clear();  // not on the wire
}

void FromC(const srics_InteractionGraph& in, rl::GraphUpdate* out) {
  Fields(FromCOp{}, *out, in);
  out->structure.partner.clear();  // not on the wire
}

void FromC(const srics_EvalResult& in, rl::EvalReport* out) {
  Fields(FromCOp{}, *out, in);
  out->summary.selectivity = in.selectivity;
  out->summary.selectivity_episodes = out->summary.episodes;
}

}  // namespace internal

namespace {

template <typename T>
T RoundTrip(const T& value) {
  typename internal::CType<T>::type sample;
  internal::SequenceBuffers buffers;
  internal::ToC(value, {}, &sample, &buffers);
  T received;
  internal::FromC(sample, &received);
  return received;
}

}  // namespace

rl::LearnerReport AsReceived(const rl::LearnerReport& value) { return RoundTrip(value); }
rl::EvalReport AsReceived(const rl::EvalReport& value) { return RoundTrip(value); }
rl::GraphUpdate AsReceived(const rl::GraphUpdate& value) { return RoundTrip(value); }

}  // namespace srics::transport
