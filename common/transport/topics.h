#pragma once
// The one table of topics: name, keys and QoS of every topic of the contract. Writers and
// readers of this library build their DDS QoS from it; idl/README.md documents the same
// table for external monitors (keep the two in step).

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace srics::transport {

enum class TopicId { kEpisode, kPolicyWeights, kInteractionGraph, kEvalResult, kLearnerStats, kNodeStatus };

enum class Durability { kVolatile, kTransientLocal };

// Where a history depth comes from: a constant or TransportConfig::episode_history_depth.
enum class HistoryKind {
  kKeepLast,        // keep the last `depth` samples per instance
  kKeepAllBounded,  // keep all; the reader holds at most episode_history_depth samples, so a
                    // full reader throttles the writer instead of losing data
};

struct TopicSpec {
  TopicId id;
  std::string_view name;       // DDS topic name
  std::string_view type_name;  // DDS type name (from the IDL module)
  std::string_view keys;       // key fields, "" for event topics without key
  Durability durability;
  HistoryKind history;
  int32_t depth;          // for kKeepLast
  bool liveliness_lease;  // writers offer AUTOMATIC liveliness with the configured lease
  // The sample names its sender (Episode and EvalResult: actor_id; NodeStatus: role and
  // node_id). Under DDS Security its writers write in the partition of their identity and its
  // readers refuse a sample whose sender is not that identity (SenderIdentity).
  bool names_sender;
};

// Every topic is RELIABLE. Order follows TopicId.
inline constexpr std::array<TopicSpec, 6> kTopics = {{
    {TopicId::kEpisode, "srics/episode", "srics::Episode", "", Durability::kVolatile, HistoryKind::kKeepAllBounded, 0,
     false, true},
    {TopicId::kPolicyWeights, "srics/policy_weights", "srics::PolicyWeights", "run_id", Durability::kTransientLocal,
     HistoryKind::kKeepLast, 1, false, false},
    {TopicId::kInteractionGraph, "srics/interaction_graph", "srics::InteractionGraph", "run_id",
     Durability::kTransientLocal, HistoryKind::kKeepLast, 1, false, false},
    {TopicId::kEvalResult, "srics/eval_result", "srics::EvalResult", "", Durability::kVolatile, HistoryKind::kKeepLast,
     64, false, true},
    {TopicId::kLearnerStats, "srics/learner_stats", "srics::LearnerStats", "run_id", Durability::kVolatile,
     HistoryKind::kKeepLast, 1, false, false},
    {TopicId::kNodeStatus, "srics/node_status", "srics::NodeStatus", "run_id, role, node_id",
     Durability::kTransientLocal, HistoryKind::kKeepLast, 1, true, true},
}};

// The row of `id`.
constexpr const TopicSpec& Spec(TopicId id) { return kTopics[static_cast<size_t>(id)]; }

// The keystore identity that may speak for a sender (deploy/security/make-keystore.sh names
// them so): "actor-K" for actor K, the role itself for the one learner, graph service and
// launcher of a run ("learner", "graph", "launcher"). Under DDS Security a sample that names
// a sender (TopicSpec::names_sender) is accepted only from a writer in that partition, which
// that identity's signed permissions alone allow.
std::string SenderIdentity(std::string_view role, uint32_t id);

}  // namespace srics::transport
