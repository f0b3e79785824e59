#pragma once
// The one table of topics: name, keys and QoS of every topic of the contract. Writers and
// readers of this library build their DDS QoS from it; idl/README.md documents the same
// table for external monitors (keep the two in step).

#include <array>
#include <cstdint>
#include <string_view>

namespace srics::transport {

enum class TopicId { kEpisode, kPolicyWeights, kInteractionGraph, kEvalResult, kLearnerStats,
                     kNodeStatus };

enum class Durability { kVolatile, kTransientLocal };

// Where a history depth comes from: a constant or TransportConfig::episode_history_depth.
enum class HistoryKind {
  kKeepLast,         // keep the last `depth` samples per instance
  kKeepAllBounded,   // keep all; the reader holds at most episode_history_depth samples, so a
                     // full reader throttles the writer instead of losing data
};

struct TopicSpec {
  TopicId id;
  std::string_view name;       // DDS topic name
  std::string_view type_name;  // DDS type name (from the IDL module)
  std::string_view keys;       // key fields, "" for event topics without key
  Durability durability;
  HistoryKind history;
  int32_t depth;               // for kKeepLast
  bool liveliness_lease;       // writers offer AUTOMATIC liveliness with the configured lease
};

// Every topic is RELIABLE. Order follows TopicId.
inline constexpr std::array<TopicSpec, 6> kTopics = {{
    {TopicId::kEpisode, "srics/episode", "srics::Episode", "", Durability::kVolatile,
     HistoryKind::kKeepAllBounded, 0, false},
    {TopicId::kPolicyWeights, "srics/policy_weights", "srics::PolicyWeights", "run_id",
     Durability::kTransientLocal, HistoryKind::kKeepLast, 1, false},
    {TopicId::kInteractionGraph, "srics/interaction_graph", "srics::InteractionGraph", "run_id",
     Durability::kTransientLocal, HistoryKind::kKeepLast, 1, false},
    {TopicId::kEvalResult, "srics/eval_result", "srics::EvalResult", "", Durability::kVolatile,
     HistoryKind::kKeepLast, 64, false},
    {TopicId::kLearnerStats, "srics/learner_stats", "srics::LearnerStats", "run_id",
     Durability::kVolatile, HistoryKind::kKeepLast, 1, false},
    {TopicId::kNodeStatus, "srics/node_status", "srics::NodeStatus", "run_id, role, node_id",
     Durability::kTransientLocal, HistoryKind::kKeepLast, 1, true},
}};

// The row of `id`.
constexpr const TopicSpec& Spec(TopicId id) { return kTopics[static_cast<size_t>(id)]; }

}  // namespace srics::transport
