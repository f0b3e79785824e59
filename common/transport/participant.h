#pragma once
// A DDS domain participant configured from TransportConfig: the domain id, the Cyclone XML
// of the chosen profile, the run id stamped on every sample, the shutdown it obeys and the
// per-topic counters of received samples.

#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include "common/config/transport_config.h"
#include "common/transport/shutdown.h"
#include "common/transport/topics.h"

namespace srics::transport {

// What the readers of one topic did with received samples, summed over the process's readers.
struct SampleCounters {
  uint64_t accepted = 0;
  uint64_t rejected = 0;   // malformed: broke the contract (logged at a limited rate)
  uint64_t other_run = 0;  // well-formed samples of another run_id (ignored silently)
};

// Internal: the live counters, shared by a participant and its readers.
struct CounterTable {
  struct Row {
    std::atomic<uint64_t> accepted{0}, rejected{0}, other_run{0};
  };
  std::array<Row, kTopics.size()> rows;
  // every rejection of a received sample by its counter name ("graph.entities"): those of the
  // readers' contract checks and those of the links' checks against the run
  void CountRejection(std::string_view counter);
  std::map<std::string, uint64_t, std::less<>> Rejections() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, uint64_t, std::less<>> rejections_;
};

// "graph.entities=2 weights.checksum=1": counters in name order, for NodeStatus.detail.
std::string RejectionSummary(const std::map<std::string, uint64_t, std::less<>>& rejections);

// The Cyclone configuration string for `config` (XML from the templates in deploy/cyclonedds/
// with the config's values filled in, or a file:// URI for profile file), or "" for profile
// environment (Cyclone then reads CYCLONEDDS_URI). Throws std::invalid_argument when the
// domain id and participant count give UDP ports above 65535.
std::string CycloneConfigFor(const config::TransportConfig& config);

class Participant {
 public:
  // Creates the domain (once per domain id in a process) and a participant in it, bound to
  // `shutdown` (which must outlive it). Throws DdsError when Cyclone refuses (bad XML, no
  // free participant index, ...), std::invalid_argument for a domain id already configured
  // differently in this process.
  explicit Participant(const config::TransportConfig& config, Shutdown& shutdown = Shutdown::Process());
  ~Participant();
  Participant(Participant&& other) noexcept;
  Participant& operator=(Participant&& other) noexcept;
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  const config::TransportConfig& config() const { return config_; }
  // The run id stamped on written samples and required of received ones.
  const std::string& run_id() const { return config_.run_id; }
  Shutdown& shutdown() const { return *shutdown_; }
  bool shutdown_requested() const { return shutdown_->requested(); }

  // Received-sample counters of one topic (all readers of this participant).
  SampleCounters counters(TopicId topic) const;
  // Received samples rejected on every topic, by the readers' contract checks and by the
  // links' checks against the run (CountRejection): NodeStatus.dropped_samples.
  uint64_t total_rejected() const;
  // Counts one rejection of a received sample under `counter` ("<topic>.<check>", the table
  // of common/transport/README.md). Readers count their own; links call it for their checks.
  void CountRejection(std::string_view counter) const { counters_->CountRejection(counter); }
  // Every rejection so far by counter.
  std::map<std::string, uint64_t, std::less<>> rejections() const { return counters_->Rejections(); }

  // Internal, for readers and writers: DDS handles and the shared counters.
  int32_t handle() const { return participant_; }
  int32_t guard() const { return guard_; }
  const std::shared_ptr<CounterTable>& counter_table() const { return counters_; }

 private:
  void Release();

  config::TransportConfig config_;
  Shutdown* shutdown_ = nullptr;
  int32_t participant_ = 0;
  int32_t guard_ = 0;  // triggered by shutdown_, attached to every reader's waitset
  bool holds_domain_ = false;
  std::shared_ptr<CounterTable> counters_;
};

}  // namespace srics::transport
