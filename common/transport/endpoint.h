#pragma once
// Typed topics, writers and readers of the domain type of each topic (rl::Episode,
// rl::WeightsUpdate, rl::GraphUpdate, rl::EvalReport, rl::LearnerReport, rl::NodeStatus): each
// goes to and from its generated C type once (convert.h). A domain type carries no envelope: a
// writer stamps its participant's (wire.h), a reader checks it and can tell the run id. Each
// owns its DDS entities (deleted in the destructor) and is move-only. QoS comes from the table
// in topics.h. The participant must outlive its endpoints.
//
//   Writer<rl::Episode> writer(participant);
//   if (writer.Write(episode) == WriteResult::kShutdown) return;   // retried back-pressure
//
//   Reader<rl::Episode> reader(participant, {.episode_limits = rl::EpisodeLimitsFor(env)});
//   rl::Episode episode;
//   switch (reader.Take(&episode, std::chrono::milliseconds(500))) {
//     case TakeStatus::kSample: ...; case TakeStatus::kTimeout: ...; case TakeStatus::kShutdown: ...
//   }
//
// Threading: one thread per endpoint at a time; different endpoints may be used from
// different threads. Shutdown::Request() may come from any thread.

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/rl/episode.h"
#include "common/rl/updates.h"
#include "common/transport/owned_entity.h"
#include "common/transport/participant.h"
#include "common/transport/topics.h"
#include "common/transport/wire.h"

namespace srics::transport {

enum class WriteResult {
  kSent,          // accepted by DDS (delivered reliably to matched readers)
  kBackPressure,  // TryWrite only: readers are behind, nothing was sent; try again later
  kShutdown,      // Write only: shutdown was requested before the sample was accepted
};

enum class TakeStatus {
  kSample,    // *out holds a validated sample of this run
  kTimeout,   // nothing valid arrived in time
  kShutdown,  // shutdown was requested (checked before taking anything)
};

struct WriterOptions {
  std::string topic_name;  // empty: the table's name (tests isolate themselves with others)
  bool stamp = true;       // rl::WeightsUpdate: set the checksum (false sends 0, for tests of readers)
  bool validate = true;    // throw InvalidMessage for what a reader would reject
  // Packs consecutive samples into shared datagrams (Cyclone write batching): a written
  // sample waits in this process until Flush(), a full datagram (64 KB on the loopback
  // profile), `batch_delay` or the writer's destruction. A datagram per sample costs more than
  // the sample itself for small samples (episodes): batching is what lets a writer reach
  // ddsperf's rate, and with a delay bound it costs a rare writer no more than that delay.
  bool batch = false;
  // With batch: the longest a written sample waits before it is sent (a thread of the writer
  // flushes it); 0: it waits for Flush(), a full datagram or the destruction.
  std::chrono::milliseconds batch_delay{0};
  // Domain types carry no envelope: their writer stamps this contract version and the
  // participant's run id. Tests set another version to check that readers refuse it.
  uint32_t contract_version = kContractVersion;
};

struct ReaderOptions {
  std::string topic_name;  // empty: the table's name
  bool all_runs = false;   // monitors: accept samples of every run_id
  // Reader<rl::Episode> only: what this run's episodes look like (also says whether states
  // carry velocities, which the wire cannot). Episodes outside them are counted as rejected.
  rl::EpisodeLimits episode_limits;
};

// The DDS topic of T in one participant. Writers and readers create their own. Move-only,
// as the entity it owns.
template <typename T>
class Topic {
 public:
  // Throws DdsError.
  Topic(const Participant& participant, const std::string& name);

  int32_t handle() const { return topic_.get(); }
  const std::string& name() const { return name_; }

 private:
  OwnedEntity topic_;
  std::string name_;
};

template <typename T>
class Writer {
 public:
  // Throws DdsError. Move-only.
  explicit Writer(const Participant& participant, WriterOptions options = {});

  // One attempt: kSent, or kBackPressure when DDS blocked for writer_max_blocking_ms without
  // room (DDS_RETCODE_TIMEOUT; nothing was sent). Throws InvalidMessage (see WriterOptions)
  // and DdsError for any other failure.
  [[nodiscard]] WriteResult TryWrite(const T& msg);
  // Retries back-pressure until the sample is accepted (kSent) or shutdown is requested
  // (kShutdown: not sent). Never returns kBackPressure.
  [[nodiscard]] WriteResult Write(const T& msg);

  // Sends what a batching writer holds back (no effect without WriterOptions::batch).
  void Flush();
  // Times the batch_delay flusher sent held-back samples (tests: 0 without a delay).
  uint64_t timed_flushes() const;

  // Readers currently matched (subscription side of the same topic and compatible QoS).
  uint32_t matched_readers() const;
  // Waits until at least `count` readers matched; false on timeout or shutdown.
  bool WaitForReaders(uint32_t count, std::chrono::milliseconds timeout);
  // Waits until every matched reader acknowledged everything written (e.g. before exiting:
  // volatile data still in flight dies with the process); false on timeout.
  bool WaitForAcks(std::chrono::milliseconds timeout);
  // Attempts that ended in back-pressure so far.
  uint64_t back_pressure_count() const { return back_pressure_; }

 private:
  struct Impl;
  // deletes the Impl in endpoint.cc, where it is complete: the destructor and moves are implicit
  struct DeleteImpl {
    void operator()(Impl* impl) const;
  };
  std::unique_ptr<Impl, DeleteImpl> impl_;
  uint64_t back_pressure_ = 0;
};

template <typename T>
class Reader {
 public:
  // Throws DdsError. Move-only.
  explicit Reader(const Participant& participant, ReaderOptions options = {});

  // Waits up to `timeout` for a valid sample of this run. Malformed samples are dropped,
  // counted and logged at a limited rate; other runs' samples are dropped and counted.
  // `run_id`, when given, receives the sample's run id (for readers of all runs).
  TakeStatus Take(T* out, std::chrono::milliseconds timeout, std::string* run_id = nullptr);
  // Waits up to `timeout` for the first valid sample, then appends every valid sample already
  // available, up to `max` in all. Returns how many were appended (0: timeout or shutdown).
  size_t TakeMany(std::vector<T>* out, size_t max, std::chrono::milliseconds timeout);

  // Writers currently matched, and those alive (by their liveliness lease).
  uint32_t matched_writers() const;
  uint32_t alive_writers() const;
  // Waits until at least `count` writers matched; false on timeout or shutdown.
  bool WaitForWriters(uint32_t count, std::chrono::milliseconds timeout);

  // What this reader did with the samples it took.
  SampleCounters counters() const;

 private:
  struct Impl;
  // deletes the Impl in endpoint.cc, where it is complete: the destructor and moves are implicit
  struct DeleteImpl {
    void operator()(Impl* impl) const;
  };
  std::unique_ptr<Impl, DeleteImpl> impl_;
};

}  // namespace srics::transport
