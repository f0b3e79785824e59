#include "common/transport/graph_feed.h"

#include <spdlog/spdlog.h>

#include <stdexcept>

#include "common/rl/graph.h"

namespace srics::transport {

GraphFeed::GraphFeed(const Participant& participant, int num_entities)
    : participant_(participant),
      num_entities_(num_entities),
      reader_(participant),
      limiter_(std::chrono::seconds(participant.config().rejected_log_interval_s)) {}

std::string AdoptComputedStructure(rl::GraphUpdate* update) {
  if (const std::string problem = rl::ValidateGraph(update->graph); !problem.empty())
    return "interaction graph: " + problem;
  rl::SubgoalStructure computed = rl::ComputeSubgoalStructure(update->graph);
  if (computed.ancestor_mask != update->structure.ancestor_mask)
    return "interaction graph: ancestor sets disagree with the adjacency";
  if (computed.depth != update->structure.depth) return "interaction graph: depths disagree with the adjacency";
  update->structure = std::move(computed);
  return "";
}

void GraphFeed::Refuse(const char* counter, uint64_t version, const std::string& why) {
  ++rejected_;
  participant_.CountRejection(counter);
  uint64_t suppressed = 0;
  if (limiter_.Allow(&suppressed))
    spdlog::warn("graph v{} refused: {} ({} refused so far, {} warnings suppressed)", version, why, rejected_,
                 suppressed);
}

std::optional<rl::GraphUpdate> GraphFeed::PollNewest() {
  rl::GraphUpdate received;
  std::optional<rl::GraphUpdate> newest;
  while (reader_.Take(&received, std::chrono::milliseconds(0)) == TakeStatus::kSample) {
    // the run's entity count first: the structure is computed only for a graph of this run
    const int n = received.graph.num_entities;
    if (num_entities_ > 0 && n != num_entities_) {
      Refuse(
          "graph.entities", received.version,
          "the graph has " + std::to_string(n) + " entities, this run's environment " + std::to_string(num_entities_));
      continue;
    }
    if (n > rl::kMaxGraphEntities) {
      Refuse(
          "graph.entities", received.version,
          std::to_string(n) + " entities, the graph algorithms take at most " + std::to_string(rl::kMaxGraphEntities));
      continue;
    }
    if (received.version == version_) continue;  // the same graph again (a restarted graph service)
    if (received.version < version_) {
      Refuse("graph.stale", received.version, "older than v" + std::to_string(version_));
      continue;
    }
    if (const std::string problem = AdoptComputedStructure(&received); !problem.empty()) {
      Refuse("graph.structure", received.version, problem);
      continue;
    }
    version_ = received.version;  // only an accepted graph moves the version
    newest = std::move(received);
  }
  return newest;
}

}  // namespace srics::transport
