#include "common/transport/endpoint.h"

#include <spdlog/spdlog.h>

#include <array>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "common/logging/logging.h"
#include "common/transport/convert.h"
#include "common/transport/dds_util.h"
#include "common/transport/validation.h"

namespace srics::transport {
namespace {

using Clock = std::chrono::steady_clock;
using internal::Check;

// Deletes a QoS object at scope exit.
struct QosHolder {
  dds_qos_t* qos;
  ~QosHolder() { dds_delete_qos(qos); }
};

std::string TopicName(TopicId id, const std::string& override_name) {
  return override_name.empty() ? std::string(Spec(id).name) : override_name;
}

// Waits on a fresh waitset holding `entity` (with `status` enabled) and the shutdown guard
// until ready() or the deadline; false on timeout or shutdown.
template <typename Ready>
bool WaitForStatus(int32_t participant, int32_t guard, const Shutdown& shutdown, int32_t entity, uint32_t status,
                   std::chrono::milliseconds timeout, Ready ready) {
  const auto deadline = Clock::now() + timeout;
  Check(dds_set_status_mask(entity, status), "dds_set_status_mask");
  const OwnedEntity owned_waitset(Check(dds_create_waitset(participant), "dds_create_waitset"));
  const int32_t waitset = owned_waitset.get();
  Check(dds_waitset_attach(waitset, entity, 0), "dds_waitset_attach");
  Check(dds_waitset_attach(waitset, guard, 0), "dds_waitset_attach");
  while (true) {
    if (shutdown.requested()) return false;
    if (ready()) return true;
    const auto left = deadline - Clock::now();
    if (left <= Clock::duration::zero()) return false;
    Check(dds_waitset_wait(waitset, nullptr, 0, internal::ToDdsDuration(left)), "dds_waitset_wait");
  }
}

// One status of `entity`, read with `get` (dds_get_..._status); throws DdsError.
template <typename Status>
Status StatusOf(dds_return_t (*get)(dds_entity_t, Status*), dds_entity_t entity, const char* what) {
  Status status;
  Check(get(entity, &status), what);
  return status;
}

// The sender a sample names (topics with TopicSpec::names_sender; the others never ask).
std::string ClaimedSender(const rl::Episode& episode) { return SenderIdentity("actor", episode.actor_id); }
std::string ClaimedSender(const rl::EvalReport& report) { return SenderIdentity("actor", report.actor_id); }
std::string ClaimedSender(const rl::NodeStatus& status) { return SenderIdentity(status.role, status.node_id); }
template <typename M>
std::string ClaimedSender(const M&) {
  return {};
}

// The short name of a topic in rejection counters ("episode" in "episode.sender").
std::string CounterPrefix(TopicId id) {
  switch (id) {
    case TopicId::kEpisode: return "episode";
    case TopicId::kPolicyWeights: return "weights";
    case TopicId::kInteractionGraph: return "graph";
    case TopicId::kEvalResult: return "eval";
    case TopicId::kLearnerStats: return "stats";
    case TopicId::kNodeStatus: return "status";
  }
  return "topic";
}

}  // namespace

// ---------------------------------------------------------------------------------- Topic

template <typename T>
Topic<T>::Topic(const Participant& participant, const std::string& name)
    : topic_(Check(
          dds_create_topic(participant.handle(), internal::CType<T>::Descriptor(), name.c_str(), nullptr, nullptr),
          ("dds_create_topic " + name).c_str())),
      name_(name) {}

// --------------------------------------------------------------------------------- Writer

template <typename T>
struct Writer<T>::Impl {
  Impl(const Participant& p, WriterOptions o)
      : options(std::move(o)),
        topic(p, TopicName(internal::CType<T>::kTopic, options.topic_name)),
        participant(p.handle()),
        guard(p.guard()),
        shutdown(&p.shutdown()),
        run_id(p.run_id()) {
    QosHolder qos{internal::CreateQos(Spec(internal::CType<T>::kTopic), internal::Side::kWriter, p.config())};
    // Cyclone takes the batching mode from the domain when the writer is created
    if (options.batch) dds_write_set_batch(true);
    writer = dds_create_writer(participant, topic.handle(), qos.qos, nullptr);
    if (options.batch) dds_write_set_batch(false);
    std::string operation = "dds_create_writer " + topic.name();
    if (writer == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY) {
      const std::string& identity = p.config().security.identity;
      operation += " (DDS Security: the permissions of identity '" + identity + "' do not allow it";
      if (Spec(internal::CType<T>::kTopic).names_sender)
        operation += " in partition '" + identity +
                     "'; a keystore made before sender partitions (2026-12-06) lacks them: run "
                     "deploy/security/make-keystore.sh on it again";
      operation += ")";
    }
    Check(writer, operation.c_str());
    if (options.batch && options.batch_delay.count() > 0) flusher = std::thread([this] { FlushLoop(); });
  }
  ~Impl() {
    if (flusher.joinable()) {
      {
        std::lock_guard lock(flush_mutex);
        stopping = true;
      }
      flush_wake.notify_one();
      flusher.join();
    }
    if (options.batch && writer > 0) dds_write_flush(writer);
    internal::DeleteEntity(&writer);
  }

  // A batching writer with a delay: notes the first held-back sample for the flusher.
  void Held() {
    if (!flusher.joinable()) return;
    std::lock_guard lock(flush_mutex);
    if (held_since) return;
    held_since = Clock::now();
    flush_wake.notify_one();
  }

  // Flushes held-back samples once the oldest waited batch_delay. dds_write and
  // dds_write_flush both take the writer's lock, so this thread never races the writing one.
  void FlushLoop() {
    std::unique_lock lock(flush_mutex);
    while (!stopping) {
      if (!held_since) {
        flush_wake.wait(lock, [&] { return stopping || held_since.has_value(); });
        continue;
      }
      const auto due = *held_since + options.batch_delay;
      if (flush_wake.wait_until(lock, due, [&] { return stopping || !held_since; })) continue;
      held_since.reset();
      lock.unlock();
      dds_write_flush(writer);
      timed_flushes.fetch_add(1, std::memory_order_relaxed);
      lock.lock();
    }
  }

  // Flush(): nothing is held back any more.
  void Flushed() {
    if (!flusher.joinable()) return;
    std::lock_guard lock(flush_mutex);
    held_since.reset();
  }

  // Stamps (the weights' checksum) and validates as configured; returns what to send.
  const T& Prepare(const T& msg) {
    if constexpr (std::is_same_v<T, rl::Episode>) {
      // the envelope is stamped on the C sample (Send); the episode is checked on its own terms
      if (options.validate)
        if (auto problem = rl::ValidateEpisode(msg, rl::LimitsOfLayout(msg.layout, msg.action_dim)); !problem.empty())
          throw InvalidMessage("not sending a malformed " + topic.name() + " sample: " + problem);
      return msg;
    } else if constexpr (std::is_same_v<T, rl::WeightsUpdate>) {
      // the checksum goes onto the C sample (Send): the megabytes are summed, never copied
      checksum = options.stamp ? ParameterChecksum(msg.parameters) : 0;
      if (options.validate)  // a checksum stamped just now is not summed again
        if (auto v = Validate(msg, envelope, options.stamp ? std::nullopt : std::optional(checksum), "");
            v.verdict == Verdict::kMalformed)
          throw InvalidMessage("not sending a malformed " + topic.name() + " sample: " + v.reason);
      return msg;
    } else {
      if (options.validate)
        if (auto v = Validate(msg, envelope, ""); v.verdict == Verdict::kMalformed)
          throw InvalidMessage("not sending a malformed " + topic.name() + " sample: " + v.reason);
      return msg;
    }
  }

  // One dds_write; kBackPressure when it timed out.
  WriteResult Send(const T& msg) {
    typename internal::CType<T>::type sample;
    if constexpr (std::is_same_v<T, rl::Episode>) {
      internal::ToC(msg, envelope, &sample);
    } else {
      internal::ToC(msg, envelope, &sample, &buffers);
      if constexpr (std::is_same_v<T, rl::WeightsUpdate>) sample.checksum = checksum;
    }
    const dds_return_t ret = dds_write(writer, &sample);
    if (ret == DDS_RETCODE_TIMEOUT) return WriteResult::kBackPressure;
    Check(ret, ("dds_write " + topic.name()).c_str());
    Held();
    return WriteResult::kSent;
  }

  WriterOptions options;
  Topic<T> topic;
  int32_t participant;
  int32_t guard;
  Shutdown* shutdown;
  std::string run_id;
  int32_t writer = 0;
  uint32_t checksum = 0;  // rl::WeightsUpdate: of the prepared sample (0 without stamp)
  Envelope envelope{options.contract_version, run_id};
  internal::SequenceBuffers buffers;  // what Send converts (doubles sent as floats)
  // the batch_delay flusher (batching writers with a delay only)
  std::mutex flush_mutex;
  std::condition_variable flush_wake;
  std::optional<Clock::time_point> held_since;  // the oldest sample not yet flushed
  bool stopping = false;
  std::atomic<uint64_t> timed_flushes{0};
  std::thread flusher;  // last: started once everything it uses exists
};

template <typename T>
Writer<T>::Writer(const Participant& participant, WriterOptions options)
    : impl_(new Impl(participant, std::move(options))) {}

template <typename T>
WriteResult Writer<T>::TryWrite(const T& msg) {
  const WriteResult result = impl_->Send(impl_->Prepare(msg));
  if (result == WriteResult::kBackPressure) ++back_pressure_;
  return result;
}

template <typename T>
WriteResult Writer<T>::Write(const T& msg) {
  const T& prepared = impl_->Prepare(msg);
  while (true) {
    // each attempt blocks at most writer_max_blocking_ms inside DDS
    if (impl_->shutdown->requested()) return WriteResult::kShutdown;
    if (impl_->Send(prepared) == WriteResult::kSent) return WriteResult::kSent;
    ++back_pressure_;
  }
}

template <typename T>
void Writer<T>::Flush() {
  if (!impl_->options.batch) return;
  impl_->Flushed();
  dds_write_flush(impl_->writer);
}

template <typename T>
uint64_t Writer<T>::timed_flushes() const {
  return impl_->timed_flushes.load(std::memory_order_relaxed);
}

template <typename T>
uint32_t Writer<T>::matched_readers() const {
  return StatusOf(dds_get_publication_matched_status, impl_->writer, "dds_get_publication_matched_status")
      .current_count;
}

template <typename T>
bool Writer<T>::WaitForReaders(uint32_t count, std::chrono::milliseconds timeout) {
  return WaitForStatus(impl_->participant, impl_->guard, *impl_->shutdown, impl_->writer,
                       DDS_PUBLICATION_MATCHED_STATUS, timeout, [&] { return matched_readers() >= count; });
}

template <typename T>
bool Writer<T>::WaitForAcks(std::chrono::milliseconds timeout) {
  Flush();
  const dds_return_t ret = dds_wait_for_acks(impl_->writer, DDS_MSECS(timeout.count()));
  if (ret == DDS_RETCODE_TIMEOUT) return false;
  Check(ret, "dds_wait_for_acks");
  return true;
}

// --------------------------------------------------------------------------------- Reader

template <typename T>
struct Reader<T>::Impl {
  Impl(const Participant& p, ReaderOptions o)
      : options(std::move(o)),
        topic(p, TopicName(internal::CType<T>::kTopic, options.topic_name)),
        participant(p.handle()),
        guard(p.guard()),
        shutdown(&p.shutdown()),
        run_id(options.all_runs ? std::string() : p.run_id()),
        shared(p.counter_table()),
        limiter(std::chrono::seconds(p.config().rejected_log_interval_s)),
        bind_senders(Spec(internal::CType<T>::kTopic).names_sender && !p.config().security.keystore.empty()) {
    QosHolder qos{internal::CreateQos(Spec(internal::CType<T>::kTopic), internal::Side::kReader, p.config())};
    // A writer's identity is noted when it matches: its last samples may be taken after it left
    // (an actor that wrote and exited), when DDS no longer knows it.
    dds_listener_t* listener = nullptr;
    if (bind_senders) {
      listener = dds_create_listener(this);
      dds_lset_subscription_matched(listener,
                                    [](dds_entity_t, const dds_subscription_matched_status_t status, void* self) {
                                      if (status.current_count_change > 0)
                                        static_cast<Impl*>(self)->WriterIdentity(status.last_publication_handle);
                                    });
    }
    reader = dds_create_reader(participant, topic.handle(), qos.qos, listener);
    if (listener) dds_delete_listener(listener);
    Check(reader, ("dds_create_reader " + topic.name()).c_str());
    condition = Check(dds_create_readcondition(reader, DDS_ANY_STATE), "dds_create_readcondition");
    waitset = Check(dds_create_waitset(participant), "dds_create_waitset");
    Check(dds_waitset_attach(waitset, condition, 0), "dds_waitset_attach");
    Check(dds_waitset_attach(waitset, guard, 0), "dds_waitset_attach");
  }
  ~Impl() {
    internal::DeleteEntity(&waitset);
    internal::DeleteEntity(&reader);  // also deletes the read condition
    for (auto& sample : taken) dds_sample_free(&sample, internal::CType<T>::Descriptor(), DDS_FREE_CONTENTS);
  }

  static constexpr size_t kBatch = 16;
  static constexpr size_t kMaxWriters = 4096;

  // Takes up to `max` samples now (no waiting); appends the valid ones to *out. DDS copies
  // into this reader's own C samples (`taken`), whose sequence buffers it grows and then
  // reuses: no allocation per sample and sequence, as loaned samples would cost. Buffers are
  // kept only for accepted samples (sizes within the contract's limits).
  size_t TakeNow(std::vector<T>* out, size_t max, std::string* last_run_id = nullptr) {
    size_t appended = 0;
    while (appended < max) {
      void* samples[kBatch];
      for (size_t i = 0; i < kBatch; ++i) samples[i] = &taken[i];
      dds_sample_info_t infos[kBatch];
      const size_t want = std::min(kBatch, max - appended);
      const int32_t n = Check(dds_take(reader, samples, infos, want, static_cast<uint32_t>(want)), "dds_take");
      if (n == 0) break;
      for (int32_t i = 0; i < n; ++i) {
        // invalid_data samples only announce instance state changes (disposed, no writers)
        if (!infos[i].valid_data) continue;
        out->emplace_back();
        Validation verdict = Receive(taken[i], &out->back());
        if (verdict.ok() && bind_senders) verdict = CheckSender(out->back(), infos[i].publication_handle);
        if (Accept(verdict)) {
          ++appended;
          if (last_run_id) *last_run_id = internal::RunIdOf(taken[i]);
        } else {
          out->pop_back();
          // a refused sample leaves nothing behind, not even the buffers it made DDS grow
          dds_sample_free(&taken[i], internal::CType<T>::Descriptor(), DDS_FREE_CONTENTS);
          taken[i] = {};
        }
      }
      if (static_cast<size_t>(n) < want) break;
    }
    return appended;
  }

  // Converts and validates one received sample into *out.
  Validation Receive(const typename internal::CType<T>::type& sample, T* out) {
    if constexpr (std::is_same_v<T, rl::Episode>) {
      // the envelope first: an episode of another run or contract is never copied
      if (auto v = ValidateEnvelope(sample.contract_version, internal::RunIdOf(sample), run_id); !v.ok()) return v;
      internal::FromC(sample, options.episode_limits.velocities, out);
      if (auto problem = rl::ValidateEpisode(*out, options.episode_limits); !problem.empty())
        return {Verdict::kMalformed, std::move(problem), "episode.limits"};
      return {};
    } else if constexpr (std::is_same_v<T, rl::WeightsUpdate>) {
      internal::FromC(sample, out);
      return Validate(*out, internal::EnvelopeOf(sample), sample.checksum, run_id);
    } else {
      internal::FromC(sample, out);
      return Validate(*out, internal::EnvelopeOf(sample), run_id);
    }
  }

  // Under DDS Security: the sample must come from a writer in the partition of the identity
  // that may speak for the sender it names (SenderIdentity); an identity's permissions allow
  // its own partition only, so no identity can speak for another.
  Validation CheckSender(const T& sample, dds_instance_handle_t writer) {
    const std::string claimed = ClaimedSender(sample);
    const std::string identity = WriterIdentity(writer);
    if (identity == claimed) return {};
    return {Verdict::kMalformed, "it names " + claimed + " as its sender, but identity '" + identity + "' wrote it",
            CounterPrefix(internal::CType<T>::kTopic) + ".sender"};
  }

  // The one partition of a matched writer (its identity under DDS Security), or a description
  // of why there is none. Remembered per writer, also after it left: a writer's partition does
  // not change in Cyclone 0.10 (immutable once enabled); forgotten wholesale past kMaxWriters.
  // Called by the taking thread and by DDS's listener thread.
  std::string WriterIdentity(dds_instance_handle_t writer) {
    {
      std::lock_guard lock(identities_mutex);
      if (auto it = writer_identities.find(writer); it != writer_identities.end()) return it->second;
    }
    std::string identity = "(unknown writer)";
    if (dds_builtintopic_endpoint_t* endpoint = dds_get_matched_publication_data(reader, writer)) {
      uint32_t n = 0;
      char** partitions = nullptr;
      if (endpoint->qos && dds_qget_partition(endpoint->qos, &n, &partitions)) {
        identity = n == 1 ? std::string(partitions[0]) : "(" + std::to_string(n) + " partitions)";
        for (uint32_t k = 0; k < n; ++k) dds_free(partitions[k]);
        dds_free(partitions);
      } else {
        identity = "(default partition)";
      }
      dds_builtintopic_free_endpoint(endpoint);
    } else {
      return identity;  // not remembered: it may still match
    }
    std::lock_guard lock(identities_mutex);
    if (writer_identities.size() >= kMaxWriters) writer_identities.clear();
    writer_identities.emplace(writer, identity);
    return identity;
  }

  // Counts a verdict and (rate-limited) logs a rejection; true for an accepted sample.
  bool Accept(const Validation& v) {
    auto& row = shared->rows[static_cast<size_t>(internal::CType<T>::kTopic)];
    switch (v.verdict) {
      case Verdict::kAccept:
        ++local.accepted;
        row.accepted.fetch_add(1, std::memory_order_relaxed);
        return true;
      case Verdict::kOtherRun:
        ++local.other_run;
        row.other_run.fetch_add(1, std::memory_order_relaxed);
        return false;
      case Verdict::kMalformed: {
        ++local.rejected;
        row.rejected.fetch_add(1, std::memory_order_relaxed);
        shared->CountRejection(v.counter.empty() ? std::string(Spec(internal::CType<T>::kTopic).name) : v.counter);
        uint64_t suppressed = 0;
        if (limiter.Allow(&suppressed))
          spdlog::warn(
              "transport: dropped a malformed {} sample: {} ({} rejected so far, {} "
              "warnings suppressed)",
              topic.name(), v.reason, local.rejected, suppressed);
        return false;
      }
    }
    return false;
  }

  // Waits until data may be available; false on timeout (shutdown is checked by the caller).
  bool Wait(Clock::time_point deadline) {
    const auto left = deadline - Clock::now();
    if (left <= Clock::duration::zero()) return false;
    Check(dds_waitset_wait(waitset, nullptr, 0, internal::ToDdsDuration(left)), "dds_waitset_wait");
    return true;
  }

  ReaderOptions options;
  Topic<T> topic;
  int32_t participant;
  int32_t guard;
  Shutdown* shutdown;
  std::string run_id;  // "" = every run
  std::shared_ptr<CounterTable> shared;
  logging::RateLimiter limiter;
  SampleCounters local;
  int32_t reader = 0;
  int32_t condition = 0;
  int32_t waitset = 0;
  std::vector<T> batch;     // reused by Take
  const bool bind_senders;  // DDS Security and a topic that names its sender
  std::mutex identities_mutex;
  std::unordered_map<dds_instance_handle_t, std::string> writer_identities;  // see WriterIdentity
  // what dds_take copies into (zeroed: sequences start empty; DDS allocates them, they are
  // freed with the reader)
  std::array<typename internal::CType<T>::type, kBatch> taken{};
};

template <typename T>
Reader<T>::Reader(const Participant& participant, ReaderOptions options)
    : impl_(new Impl(participant, std::move(options))) {}

template <typename T>
TakeStatus Reader<T>::Take(T* out, std::chrono::milliseconds timeout, std::string* run_id) {
  const auto deadline = Clock::now() + timeout;
  auto& batch = impl_->batch;
  do {
    if (impl_->shutdown->requested()) return TakeStatus::kShutdown;
    batch.clear();
    if (impl_->TakeNow(&batch, 1, run_id) == 1) {
      *out = std::move(batch.front());
      return TakeStatus::kSample;
    }
  } while (impl_->Wait(deadline));
  return impl_->shutdown->requested() ? TakeStatus::kShutdown : TakeStatus::kTimeout;
}

template <typename T>
size_t Reader<T>::TakeMany(std::vector<T>* out, size_t max, std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  do {
    if (impl_->shutdown->requested()) return 0;
    if (size_t n = impl_->TakeNow(out, max); n > 0) return n;
  } while (impl_->Wait(deadline));
  return 0;
}

template <typename T>
uint32_t Reader<T>::matched_writers() const {
  return StatusOf(dds_get_subscription_matched_status, impl_->reader, "dds_get_subscription_matched_status")
      .current_count;
}

template <typename T>
uint32_t Reader<T>::alive_writers() const {
  return StatusOf(dds_get_liveliness_changed_status, impl_->reader, "dds_get_liveliness_changed_status").alive_count;
}

template <typename T>
bool Reader<T>::WaitForWriters(uint32_t count, std::chrono::milliseconds timeout) {
  return WaitForStatus(impl_->participant, impl_->guard, *impl_->shutdown, impl_->reader,
                       DDS_SUBSCRIPTION_MATCHED_STATUS, timeout, [&] { return matched_writers() >= count; });
}

template <typename T>
SampleCounters Reader<T>::counters() const {
  return impl_->local;
}

// -------------------------------------------------------------------------- Impl deleters

// Writers and readers delete their Impl here, where it is complete.
template <typename T>
void Writer<T>::DeleteImpl::operator()(Impl* impl) const {
  delete impl;
}
template <typename T>
void Reader<T>::DeleteImpl::operator()(Impl* impl) const {
  delete impl;
}

#define SRICS_INSTANTIATE(T) \
  template class Topic<T>;   \
  template class Writer<T>;  \
  template class Reader<T>;
SRICS_INSTANTIATE(rl::Episode)
SRICS_FOR_EACH_DOMAIN(SRICS_INSTANTIATE)
#undef SRICS_INSTANTIATE

}  // namespace srics::transport
