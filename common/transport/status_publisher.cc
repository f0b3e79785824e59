#include "common/transport/status_publisher.h"

#include <unistd.h>

#include <algorithm>

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
  status_.report = report;
  status_.report.rejections.clear();  // not on the wire: summed into the detail below
  status_.report.dropped += participant_->total_rejected();
  // what was rejected, per counter: the node's own checks and the transport's
  auto rejections = participant_->rejections();
  for (const auto& [counter, count] : report.rejections) rejections[counter] += count;
  std::string& detail = status_.report.detail;
  if (const std::string summary = RejectionSummary(rejections); !summary.empty()) {
    const std::string tail = "rejected: " + summary;
    detail = detail.empty() ? tail : detail + " | " + tail;
  }
  if (detail.size() > kDetailMaxLength) detail.resize(kDetailMaxLength);  // the IDL's bound
  status_.uptime_ms = static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - start_).count());
  (void)writer_.TryWrite(status_);  // a status lost to back-pressure is replaced by the next
}

bool StatusPublisher::PublishBeforeLeaving(const rl::NodeReport& report, uint32_t readers,
                                           std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  const bool matched = writer_.WaitForReaders(readers, timeout);
  Publish(report);
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
  return writer_.WaitForAcks(std::max(left, std::chrono::milliseconds(0))) && matched;
}

}  // namespace srics::transport
