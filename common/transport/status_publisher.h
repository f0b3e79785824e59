#pragma once
// Publishes a process's NodeStatus (keyed by run, role and id; transient-local, with a
// liveliness lease so monitors notice a dead process). Fills host, pid and uptime, adds
// the participant's rejected-sample count to the node's own, and appends every rejection
// counter (the node's report.rejections and the participant's) to the detail:
// "training | rejected: graph.entities=1 weights.checksum=2" (cut to the IDL's 256).

#include <chrono>
#include <memory>
#include <string>

#include "common/rl/updates.h"
#include "common/transport/endpoint.h"
#include "common/transport/participant.h"

namespace srics::transport {

class StatusPublisher {
 public:
  StatusPublisher(const Participant& participant, std::string role, uint32_t node_id);
  // Publishes now (does not block on back-pressure for long: status is best kept fresh).
  void Publish(const rl::NodeReport& report);
  // Before the process leaves: waits (within `timeout`) until `readers` readers matched, then
  // publishes and waits for their acknowledgements. A status written before a peer matched
  // this writer never reaches it (NodeStatus is volatile); false when the time ran out.
  bool PublishBeforeLeaving(const rl::NodeReport& report, uint32_t readers, std::chrono::milliseconds timeout);

 private:
  const Participant* participant_;
  Writer<rl::NodeStatus> writer_;
  rl::NodeStatus status_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace srics::transport
