#include "common/transport/convert.h"

#include <cstring>
#include <string>
#include <type_traits>

#include "common/transport/errors.h"

namespace srics::transport::internal {

static_assert(srics_CONTRACT_VERSION == kContractVersion,
              "kContractVersion (messages.h) must equal CONTRACT_VERSION (idl/srics.idl)");
static_assert(srics_EPISODE_EXPLORE == static_cast<int>(EpisodeMode::kExplore) &&
              srics_EPISODE_TRAIN == static_cast<int>(EpisodeMode::kTrain) &&
              srics_EPISODE_EVAL == static_cast<int>(EpisodeMode::kEval));
static_assert(srics_NODE_STARTING == static_cast<int>(NodeState::kStarting) &&
              srics_NODE_FAILED == static_cast<int>(NodeState::kFailed));

namespace {

// Copies a string into a bounded IDL string (char[bound + 1]).
template <size_t N>
void PutString(const std::string& in, char (&out)[N], const char* field) {
  if (in.size() >= N)
    throw InvalidMessage(std::string(field) + ": " + std::to_string(in.size()) +
                         " characters, the IDL allows " + std::to_string(N - 1));
  std::memcpy(out, in.data(), in.size());
  out[in.size()] = '\0';
}

// Reads a bounded IDL string; never reads past the array even without a terminating NUL.
template <size_t N>
std::string GetString(const char (&in)[N]) {
  return std::string(in, strnlen(in, N));
}

// Points a DDS sequence at a vector's storage (DDS only reads it while writing).
template <typename Seq, typename V>
void Borrow(const std::vector<V>& in, Seq* out) {
  using Element = std::remove_pointer_t<decltype(out->_buffer)>;
  static_assert(sizeof(Element) == sizeof(V));
  out->_buffer = reinterpret_cast<Element*>(const_cast<V*>(in.data()));
  out->_length = out->_maximum = static_cast<uint32_t>(in.size());
  out->_release = false;
}

template <typename Seq, typename V>
void Copy(const Seq& in, std::vector<V>* out) {
  static_assert(sizeof(*in._buffer) == sizeof(V));
  if (in._length == 0 || in._buffer == nullptr) {
    out->clear();
    return;
  }
  const auto* first = reinterpret_cast<const V*>(in._buffer);
  out->assign(first, first + in._length);
}

}  // namespace

void ToC(const Episode& in, srics_Episode* out) {
  std::memset(out, 0, sizeof(*out));
  out->contract_version = in.contract_version;
  PutString(in.run_id, out->run_id, "run_id");
  out->actor_id = in.actor_id;
  out->episode_id = in.episode_id;
  out->mode = static_cast<srics_EpisodeMode>(in.mode);
  out->policy_version = in.policy_version;
  out->graph_version = in.graph_version;
  out->num_entities = in.num_entities;
  out->entity_dim = in.entity_dim;
  out->action_dim = in.action_dim;
  out->num_steps = in.num_steps;
  Borrow(in.entity_kinds, &out->entity_kinds);
  Borrow(in.states, &out->states);
  Borrow(in.actions, &out->actions);
  out->subgoal_entity = in.subgoal_entity;
  Borrow(in.goal, &out->goal);
  out->ancestor_mask = in.ancestor_mask;
}

void FromC(const srics_Episode& in, Episode* out) {
  out->contract_version = in.contract_version;
  out->run_id = GetString(in.run_id);
  out->actor_id = in.actor_id;
  out->episode_id = in.episode_id;
  out->mode = static_cast<EpisodeMode>(in.mode);
  out->policy_version = in.policy_version;
  out->graph_version = in.graph_version;
  out->num_entities = in.num_entities;
  out->entity_dim = in.entity_dim;
  out->action_dim = in.action_dim;
  out->num_steps = in.num_steps;
  Copy(in.entity_kinds, &out->entity_kinds);
  Copy(in.states, &out->states);
  Copy(in.actions, &out->actions);
  out->subgoal_entity = in.subgoal_entity;
  Copy(in.goal, &out->goal);
  out->ancestor_mask = in.ancestor_mask;
}

void ToC(const PolicyWeights& in, srics_PolicyWeights* out) {
  std::memset(out, 0, sizeof(*out));
  out->contract_version = in.contract_version;
  PutString(in.run_id, out->run_id, "run_id");
  out->version = in.version;
  out->update_count = in.update_count;
  PutString(in.architecture, out->architecture, "architecture");
  out->checksum = in.checksum;
  Borrow(in.parameters, &out->parameters);
}

void FromC(const srics_PolicyWeights& in, PolicyWeights* out) {
  out->contract_version = in.contract_version;
  out->run_id = GetString(in.run_id);
  out->version = in.version;
  out->update_count = in.update_count;
  out->architecture = GetString(in.architecture);
  out->checksum = in.checksum;
  Copy(in.parameters, &out->parameters);
}

void ToC(const InteractionGraph& in, srics_InteractionGraph* out) {
  std::memset(out, 0, sizeof(*out));
  out->contract_version = in.contract_version;
  PutString(in.run_id, out->run_id, "run_id");
  out->version = in.version;
  out->num_entities = in.num_entities;
  Borrow(in.mean_weights, &out->mean_weights);
  Borrow(in.adjacency, &out->adjacency);
  out->action_entity = in.action_entity;
  out->threshold = in.threshold;
  Borrow(in.ancestor_masks, &out->ancestor_masks);
  Borrow(in.depths, &out->depths);
  out->held_out_loss = in.held_out_loss;
  out->training_updates = in.training_updates;
  out->episodes_used = in.episodes_used;
}

void FromC(const srics_InteractionGraph& in, InteractionGraph* out) {
  out->contract_version = in.contract_version;
  out->run_id = GetString(in.run_id);
  out->version = in.version;
  out->num_entities = in.num_entities;
  Copy(in.mean_weights, &out->mean_weights);
  Copy(in.adjacency, &out->adjacency);
  out->action_entity = in.action_entity;
  out->threshold = in.threshold;
  Copy(in.ancestor_masks, &out->ancestor_masks);
  Copy(in.depths, &out->depths);
  out->held_out_loss = in.held_out_loss;
  out->training_updates = in.training_updates;
  out->episodes_used = in.episodes_used;
}

void ToC(const EvalResult& in, srics_EvalResult* out) {
  std::memset(out, 0, sizeof(*out));
  out->contract_version = in.contract_version;
  PutString(in.run_id, out->run_id, "run_id");
  out->actor_id = in.actor_id;
  out->policy_version = in.policy_version;
  out->graph_version = in.graph_version;
  out->env_steps = in.env_steps;
  out->episodes = in.episodes;
  out->avg_distance = in.avg_distance;
  out->avg_object_distance = in.avg_object_distance;
  out->success_rate = in.success_rate;
  Borrow(in.entity_distance, &out->entity_distance);
  Borrow(in.subgoal_success, &out->subgoal_success);
  out->selectivity = in.selectivity;
}

void FromC(const srics_EvalResult& in, EvalResult* out) {
  out->contract_version = in.contract_version;
  out->run_id = GetString(in.run_id);
  out->actor_id = in.actor_id;
  out->policy_version = in.policy_version;
  out->graph_version = in.graph_version;
  out->env_steps = in.env_steps;
  out->episodes = in.episodes;
  out->avg_distance = in.avg_distance;
  out->avg_object_distance = in.avg_object_distance;
  out->success_rate = in.success_rate;
  Copy(in.entity_distance, &out->entity_distance);
  Copy(in.subgoal_success, &out->subgoal_success);
  out->selectivity = in.selectivity;
}

void ToC(const LearnerStats& in, srics_LearnerStats* out) {
  std::memset(out, 0, sizeof(*out));
  out->contract_version = in.contract_version;
  PutString(in.run_id, out->run_id, "run_id");
  out->updates = in.updates;
  out->transitions_inserted = in.transitions_inserted;
  out->training_env_steps = in.training_env_steps;
  out->budget_env_steps = in.budget_env_steps;
  out->replay_size = in.replay_size;
  out->episodes_accepted = in.episodes_accepted;
  out->episodes_rejected = in.episodes_rejected;
  out->policy_version = in.policy_version;
  out->q_loss = in.q_loss;
  out->policy_loss = in.policy_loss;
  out->alpha = in.alpha;
  out->entropy = in.entropy;
  out->updates_per_second = in.updates_per_second;
  out->inserts_per_second = in.inserts_per_second;
  out->mean_reward = in.mean_reward;
}

void FromC(const srics_LearnerStats& in, LearnerStats* out) {
  out->contract_version = in.contract_version;
  out->run_id = GetString(in.run_id);
  out->updates = in.updates;
  out->transitions_inserted = in.transitions_inserted;
  out->training_env_steps = in.training_env_steps;
  out->budget_env_steps = in.budget_env_steps;
  out->replay_size = in.replay_size;
  out->episodes_accepted = in.episodes_accepted;
  out->episodes_rejected = in.episodes_rejected;
  out->policy_version = in.policy_version;
  out->q_loss = in.q_loss;
  out->policy_loss = in.policy_loss;
  out->alpha = in.alpha;
  out->entropy = in.entropy;
  out->updates_per_second = in.updates_per_second;
  out->inserts_per_second = in.inserts_per_second;
  out->mean_reward = in.mean_reward;
}

void ToC(const NodeStatus& in, srics_NodeStatus* out) {
  std::memset(out, 0, sizeof(*out));
  out->contract_version = in.contract_version;
  PutString(in.run_id, out->run_id, "run_id");
  PutString(in.role, out->role, "role");
  out->node_id = in.node_id;
  PutString(in.host, out->host, "host");
  out->pid = in.pid;
  out->state = static_cast<srics_NodeState>(in.state);
  out->policy_version = in.policy_version;
  out->graph_version = in.graph_version;
  out->env_steps = in.env_steps;
  out->dropped_samples = in.dropped_samples;
  out->uptime_ms = in.uptime_ms;
  PutString(in.detail, out->detail, "detail");
}

void FromC(const srics_NodeStatus& in, NodeStatus* out) {
  out->contract_version = in.contract_version;
  out->run_id = GetString(in.run_id);
  out->role = GetString(in.role);
  out->node_id = in.node_id;
  out->host = GetString(in.host);
  out->pid = in.pid;
  out->state = static_cast<NodeState>(in.state);
  out->policy_version = in.policy_version;
  out->graph_version = in.graph_version;
  out->env_steps = in.env_steps;
  out->dropped_samples = in.dropped_samples;
  out->uptime_ms = in.uptime_ms;
  out->detail = GetString(in.detail);
}

}  // namespace srics::transport::internal
