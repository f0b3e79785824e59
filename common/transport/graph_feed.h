#pragma once
// The newest interaction graph of the run as the algorithms use it: taken from the topic,
// checked (ancestor sets and depths are recomputed and must agree with the sample), and
// converted. Actors and the learner each keep one.

#include <cstdint>
#include <optional>

#include "common/rl/updates.h"
#include "common/transport/endpoint.h"
#include "common/transport/messages.h"
#include "common/transport/participant.h"

namespace srics::transport {

class GraphFeed {
 public:
  explicit GraphFeed(const Participant& participant) : reader_(participant) {}
  // The newest graph with a version above every one returned before, if any (non-blocking).
  // A sample that fails the checks is counted and logged, never returned.
  std::optional<rl::GraphUpdate> PollNewest();
  uint64_t rejected() const { return rejected_; }

 private:
  Reader<InteractionGraph> reader_;
  uint64_t version_ = 0;
  uint64_t rejected_ = 0;
};

}  // namespace srics::transport
