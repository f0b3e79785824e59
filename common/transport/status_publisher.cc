#include "common/transport/status_publisher.h"

#include <unistd.h>

#include "common/transport/rl_convert.h"

namespace srics::transport {

StatusPublisher::StatusPublisher(const Participant& participant, std::string role, uint32_t node_id)
    : participant_(&participant), writer_(participant), start_(std::chrono::steady_clock::now()) {
  char host[kHostMaxLength] = {};
  gethostname(host, sizeof host - 1);
  status_.role = std::move(role);
  status_.node_id = node_id;
  status_.host = host;
  status_.pid = static_cast<int32_t>(getpid());
}

void StatusPublisher::Publish(const rl::NodeReport& report) {
  NodeStatus fresh = ToMessage(report, status_.role, status_.node_id);
  fresh.host = std::move(status_.host);
  fresh.pid = status_.pid;
  status_ = std::move(fresh);
  status_.dropped_samples += participant_->total_rejected();
  status_.uptime_ms = static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                                std::chrono::steady_clock::now() - start_)
                                                .count());
  (void)writer_.TryWrite(status_);  // a status lost to back-pressure is replaced by the next
}

}  // namespace srics::transport
