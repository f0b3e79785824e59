#pragma once
// The links of common/links/links.h over DDS: what a role process hands its loop. Each owns
// its readers and writers (the participant must outlive it); none holds any algorithm.
// Every received sample is checked before anything is computed from it: the contract (the
// readers, validation.h), then the run: episodes against its rl::EpisodeLimits, graphs against
// its entity count (limits.num_kinds: the arm and every object; 0 = any), learner stats
// against its budget. What is refused is counted per reason (Participant::CountRejection, shown
// in NodeStatus), logged at a limited rate, never handed on, and changes no state.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "common/links/links.h"
#include "common/logging/logging.h"
#include "common/rl/episode.h"
#include "common/transport/endpoint.h"
#include "common/transport/graph_feed.h"
#include "common/transport/participant.h"
#include "common/transport/status_publisher.h"

namespace srics::transport {

// The options of an actor's episode writer, shared with the transport bench so that it
// measures this path: no validation in the writer (PublishEpisode checked the episode against
// the run's limits), batched with transport.episode_batch_ms as the delay bound (0: unbatched).
WriterOptions ActorEpisodeWriterOptions(const config::TransportConfig& config);

// An actor's side: the newest weights, graph and learner stats in; episodes, evaluations and
// status out.
class DdsActorLink final : public links::ActorLink {
 public:
  // Waits up to `wait_for_readers` for the learner and the graph service to match the episode
  // writer: episodes are volatile, so what is written before they listen is lost.
  // `budget_env_steps` is the run's (run.total_env_steps): learner stats must carry it.
  DdsActorLink(const Participant& participant, uint32_t actor_id, const rl::EpisodeLimits& limits,
               uint64_t budget_env_steps, std::chrono::milliseconds wait_for_readers = std::chrono::seconds(3));

  std::optional<rl::WeightsUpdate> PollWeights(uint64_t newer_than) override;
  std::optional<rl::GraphUpdate> PollGraph() override;
  // Stats that rl::ImplausibleProgress refuses (another budget, counters that cannot be the
  // learner's) are counted as "stats.implausible" and never returned: a stray sample cannot
  // end the run for the actors or hold them back.
  std::optional<rl::LearnerProgress> PollLearner(std::chrono::milliseconds wait) override;
  // An episode outside the run's limits is not sent: it is logged and counted (rejected())
  // and true is returned (the loop goes on). False only when shutdown stopped the write.
  bool PublishEpisode(const rl::Episode& episode) override;
  void PublishEval(const rl::EvalReport& report) override;
  void PublishStatus(const rl::NodeReport& report) override;

  // Own episodes refused before sending plus graphs refused on arrival.
  uint64_t rejected() const { return episodes_refused_ + graphs_.rejected(); }
  // Learner stats refused as implausible.
  uint64_t stats_rejected() const { return stats_refused_; }

 private:
  const Participant& participant_;
  rl::EpisodeLimits limits_;
  uint64_t budget_env_steps_;
  Reader<rl::WeightsUpdate> weights_;
  GraphFeed graphs_;
  Reader<rl::LearnerReport> stats_;
  Writer<rl::Episode> episodes_;
  Writer<rl::EvalReport> evals_;
  StatusPublisher status_;
  logging::RateLimiter limiter_, stats_limiter_;
  uint64_t episodes_refused_ = 0;
  uint64_t stats_refused_ = 0;
  std::optional<rl::LearnerProgress> progress_;
};

// The learner's side: episodes and graphs in; weights, stats and status out.
class DdsLearnerLink final : public links::LearnerLink {
 public:
  DdsLearnerLink(const Participant& participant, const rl::EpisodeLimits& limits);

  size_t TakeEpisodes(std::vector<rl::Episode>* out, size_t max, std::chrono::milliseconds wait) override;
  std::optional<rl::GraphUpdate> PollGraph() override;
  // Retries back-pressure; on the way out (shutdown) one plain attempt still goes out. The
  // writer stamps run id and contract version and the checksum on the C sample, which borrows
  // the parameters: no copy of the megabytes on the way.
  void PublishWeights(rl::WeightsUpdate weights) override;
  // episodes_rejected also counts the episodes this link refused.
  void PublishStats(const rl::LearnerReport& report) override;
  void PublishStatus(const rl::NodeReport& report) override;

  // Episodes refused on arrival (malformed, outside the run's limits).
  uint64_t rejected() const { return episodes_.counters().rejected; }

 private:
  Reader<rl::Episode> episodes_;
  GraphFeed graphs_;
  Writer<rl::WeightsUpdate> weights_;
  Writer<rl::LearnerReport> stats_;
  StatusPublisher status_;
};

// The graph service's explore episodes. A thread keeps taking samples all the time, also
// while the GNN trains: the Episode topic is reliable keep-all, so a reader that stops taking
// would hold every actor back. Training episodes are for the learner and are skipped unless
// `training_episodes` (graph.refine_after_publish); episodes beyond `max_pending` not yet
// polled are dropped (counted in surplus()).
class DdsEpisodeSource final : public links::EpisodeSource {
 public:
  DdsEpisodeSource(const Participant& participant, const rl::EpisodeLimits& limits, size_t max_pending,
                   bool training_episodes = false);
  ~DdsEpisodeSource() override;
  DdsEpisodeSource(const DdsEpisodeSource&) = delete;
  DdsEpisodeSource& operator=(const DdsEpisodeSource&) = delete;

  // False once shutdown was requested.
  bool Poll(std::chrono::milliseconds timeout, std::vector<rl::Episode>* out) override;
  uint64_t rejected() const { return rejected_; }
  uint64_t surplus() const { return surplus_; }

 private:
  void TakeLoop();

  const Participant& participant_;
  size_t max_pending_;
  bool training_episodes_;
  Reader<rl::Episode> reader_;  // used by the taker thread only
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<rl::Episode> pending_;
  std::atomic<uint64_t> rejected_{0}, surplus_{0};
  std::atomic<bool> running_{true};
  std::thread taker_;  // last: starts once everything it uses exists
};

// The graph service's output: the InteractionGraph topic and its NodeStatus. Publish and
// PublishStatus use different writers, so they may be called from different threads (the
// service reports status from a heartbeat while the GNN trains).
class DdsGraphSink final : public links::GraphSink {
 public:
  explicit DdsGraphSink(const Participant& participant);
  // Throws std::runtime_error when shutdown stopped the write.
  void Publish(const rl::GraphUpdate& graph) override;
  void PublishStatus(const rl::NodeReport& report) override;

 private:
  Writer<rl::GraphUpdate> writer_;
  StatusPublisher status_;
};

}  // namespace srics::transport
