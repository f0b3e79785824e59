#pragma once
// The newest interaction graph of the run as the algorithms use it: taken from the topic,
// checked against the run (its entity count, before anything is computed from the sample),
// its ancestor sets and depths recomputed (they must agree with the sample), and converted.
// Actors and the learner each keep one.

#include <chrono>
#include <cstdint>
#include <optional>

#include "common/logging/logging.h"
#include "common/rl/updates.h"
#include "common/transport/endpoint.h"
#include "common/transport/participant.h"

namespace srics::transport {

// Replaces the structure `update` came with (its ancestor masks and depths) by the one computed
// from its adjacency. Returns why not, leaving `update` as it was, when the adjacency is not a
// graph or the two disagree (a peer with a different algorithm or a corrupted sample).
std::string AdoptComputedStructure(rl::GraphUpdate* update);

class GraphFeed {
 public:
  // `num_entities`: the run's entity count (the arm and every object); 0 accepts any count the
  // graph algorithms take (rl::kMaxGraphEntities).
  GraphFeed(const Participant& participant, int num_entities);
  // The newest graph with a version above every one returned before, if any (non-blocking).
  // A sample that fails the checks is counted (per reason, in the participant: graph.entities,
  // graph.structure, graph.stale for an older version; the same version again is skipped), logged at a limited rate,
  // never returned, and leaves the version where it was: a refused graph with a huge version does not hide the next
  // good one.
  std::optional<rl::GraphUpdate> PollNewest();
  uint64_t rejected() const { return rejected_; }

 private:
  void Refuse(const char* counter, uint64_t version, const std::string& why);

  const Participant& participant_;
  int num_entities_;
  Reader<rl::GraphUpdate> reader_;
  logging::RateLimiter limiter_;
  uint64_t version_ = 0;
  uint64_t rejected_ = 0;
};

}  // namespace srics::transport
