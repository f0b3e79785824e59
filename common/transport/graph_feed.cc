#include "common/transport/graph_feed.h"

#include <spdlog/spdlog.h>

#include <stdexcept>

#include "common/rl/graph.h"
#include "common/transport/rl_convert.h"

namespace srics::transport {

GraphFeed::GraphFeed(const Participant& participant, int num_entities)
    : participant_(participant),
      num_entities_(num_entities),
      reader_(participant),
      limiter_(std::chrono::seconds(participant.config().rejected_log_interval_s)) {}

void GraphFeed::Refuse(const char* counter, const InteractionGraph& message, const std::string& why) {
  ++rejected_;
  participant_.CountRejection(counter);
  uint64_t suppressed = 0;
  if (limiter_.Allow(&suppressed))
    spdlog::warn("graph v{} refused: {} ({} refused so far, {} warnings suppressed)", message.version, why, rejected_,
                 suppressed);
}

std::optional<rl::GraphUpdate> GraphFeed::PollNewest() {
  InteractionGraph message;
  std::optional<rl::GraphUpdate> newest;
  while (reader_.Take(&message, std::chrono::milliseconds(0)) == TakeStatus::kSample) {
    // the run's entity count first: the structure is computed only for a graph of this run
    if (num_entities_ > 0 && message.num_entities != num_entities_) {
      Refuse("graph.entities", message,
             "the graph has " + std::to_string(message.num_entities) + " entities, this run's environment " +
                 std::to_string(num_entities_));
      continue;
    }
    if (message.num_entities > rl::kMaxGraphEntities) {
      Refuse("graph.entities", message,
             std::to_string(message.num_entities) + " entities, the graph algorithms take at most " +
                 std::to_string(rl::kMaxGraphEntities));
      continue;
    }
    if (message.version == version_) continue;  // the same graph again (a restarted graph service)
    if (message.version < version_) {
      Refuse("graph.stale", message, "older than v" + std::to_string(version_));
      continue;
    }
    try {
      newest = FromMessage(message);
      version_ = newest->version;  // only an accepted graph moves the version
    } catch (const std::invalid_argument& e) {
      Refuse("graph.structure", message, e.what());
    }
  }
  return newest;
}

}  // namespace srics::transport
