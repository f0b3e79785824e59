#include "common/transport/dds_links.h"

#include <spdlog/spdlog.h>

#include <stdexcept>

namespace srics::transport {
namespace {

ReaderOptions EpisodeReaderOptions(const rl::EpisodeLimits& limits) {
  ReaderOptions options;
  options.episode_limits = limits;
  return options;
}

std::chrono::milliseconds LogInterval(const Participant& participant) {
  return std::chrono::seconds(participant.config().rejected_log_interval_s);
}

}  // namespace

WriterOptions ActorEpisodeWriterOptions(const config::TransportConfig& config) {
  WriterOptions options;
  options.validate = false;  // the link checked the episode against the run's limits already
  options.batch = config.episode_batch_ms > 0;
  options.batch_delay = std::chrono::milliseconds(config.episode_batch_ms);
  return options;
}

// ------------------------------------------------------------------------------ actor link

DdsActorLink::DdsActorLink(const Participant& participant, uint32_t actor_id, const rl::EpisodeLimits& limits,
                           uint64_t budget_env_steps, std::chrono::milliseconds wait_for_readers)
    : participant_(participant),
      limits_(limits),
      budget_env_steps_(budget_env_steps),
      weights_(participant),
      graphs_(participant, limits.num_kinds),
      stats_(participant),
      episodes_(participant, ActorEpisodeWriterOptions(participant.config())),
      evals_(participant),
      status_(participant, "actor", actor_id),
      limiter_(LogInterval(participant)),
      stats_limiter_(LogInterval(participant)) {
  // the learner and the graph service; go on without them after that
  episodes_.WaitForReaders(2, wait_for_readers);
}

std::optional<rl::WeightsUpdate> DdsActorLink::PollWeights(uint64_t newer_than) {
  // no version is kept here: the actor keeps the version of the weights it accepted
  rl::WeightsUpdate received;
  std::optional<rl::WeightsUpdate> newest;
  while (weights_.Take(&received, std::chrono::milliseconds(0)) == TakeStatus::kSample) {
    if (received.version <= newer_than || (newest && received.version <= newest->version)) continue;
    newest = std::move(received);  // megabytes: moved, not copied
  }
  return newest;
}

std::optional<rl::GraphUpdate> DdsActorLink::PollGraph() { return graphs_.PollNewest(); }

std::optional<rl::LearnerProgress> DdsActorLink::PollLearner(std::chrono::milliseconds wait) {
  rl::LearnerReport report;
  for (auto timeout = wait; stats_.Take(&report, timeout) == TakeStatus::kSample;
       timeout = std::chrono::milliseconds(0)) {
    const rl::LearnerProgress progress = report.progress();
    if (const std::string problem = rl::ImplausibleProgress(progress, budget_env_steps_); !problem.empty()) {
      ++stats_refused_;
      participant_.CountRejection("stats.implausible");
      uint64_t suppressed = 0;
      if (stats_limiter_.Allow(&suppressed))
        spdlog::warn("learner stats refused: {} ({} refused so far, {} warnings suppressed)", problem, stats_refused_,
                     suppressed);
      continue;
    }
    progress_ = progress;
  }
  return progress_;
}

bool DdsActorLink::PublishEpisode(const rl::Episode& episode) {
  if (auto problem = rl::ValidateEpisode(episode, limits_); !problem.empty()) {
    ++episodes_refused_;
    uint64_t suppressed = 0;
    if (limiter_.Allow(&suppressed))
      spdlog::warn("own episode {} not sent: {} ({} refused so far, {} warnings suppressed)", episode.episode_id,
                   problem, episodes_refused_, suppressed);
    return true;
  }
  return episodes_.Write(episode) == WriteResult::kSent;
}

void DdsActorLink::PublishEval(const rl::EvalReport& report) {
  if (evals_.Write(report) != WriteResult::kSent) spdlog::warn("evaluation not sent: shutting down");
}

void DdsActorLink::PublishStatus(const rl::NodeReport& report) {
  rl::NodeReport r = report;
  // the participant adds what its readers and links refused (graphs and stats among them)
  r.dropped += episodes_refused_;
  if (episodes_refused_ > 0) r.rejections["episode.own"] += episodes_refused_;
  status_.Publish(r);
}

// ---------------------------------------------------------------------------- learner link

DdsLearnerLink::DdsLearnerLink(const Participant& participant, const rl::EpisodeLimits& limits)
    : episodes_(participant, EpisodeReaderOptions(limits)),
      graphs_(participant, limits.num_kinds),
      weights_(participant),
      stats_(participant),
      status_(participant, "learner", 0) {}

size_t DdsLearnerLink::TakeEpisodes(std::vector<rl::Episode>* out, size_t max, std::chrono::milliseconds wait) {
  return episodes_.TakeMany(out, max, wait);
}

std::optional<rl::GraphUpdate> DdsLearnerLink::PollGraph() { return graphs_.PollNewest(); }

void DdsLearnerLink::PublishWeights(rl::WeightsUpdate weights) {
  if (weights_.Write(weights) != WriteResult::kSent && weights_.TryWrite(weights) != WriteResult::kSent)
    spdlog::info("weights v{} not sent: shutting down", weights.version);
}

void DdsLearnerLink::PublishStats(const rl::LearnerReport& report) {
  rl::LearnerReport r = report;
  r.episodes_rejected += rejected();
  (void)stats_.TryWrite(r);  // stats lost to back-pressure are replaced by the next
}

void DdsLearnerLink::PublishStatus(const rl::NodeReport& report) {
  status_.Publish(report);  // the participant adds what its readers and the graph feed refused
}

// -------------------------------------------------------------------------- episode source

DdsEpisodeSource::DdsEpisodeSource(const Participant& participant, const rl::EpisodeLimits& limits, size_t max_pending,
                                   bool training_episodes)
    : participant_(participant),
      max_pending_(max_pending),
      training_episodes_(training_episodes),
      reader_(participant, EpisodeReaderOptions(limits)),
      taker_([this] { TakeLoop(); }) {}

DdsEpisodeSource::~DdsEpisodeSource() {
  running_ = false;
  taker_.join();
}

bool DdsEpisodeSource::Poll(std::chrono::milliseconds timeout, std::vector<rl::Episode>* out) {
  std::unique_lock lock(mutex_);
  arrived_.wait_for(lock, timeout, [&] { return !pending_.empty() || participant_.shutdown_requested(); });
  for (auto& e : pending_) out->push_back(std::move(e));
  pending_.clear();
  return !participant_.shutdown_requested();
}

void DdsEpisodeSource::TakeLoop() {
  std::vector<rl::Episode> taken;
  while (running_ && !participant_.shutdown_requested()) {
    taken.clear();
    reader_.TakeMany(&taken, 256, std::chrono::milliseconds(100));
    rejected_ = reader_.counters().rejected;
    std::lock_guard lock(mutex_);
    for (auto& e : taken) {
      if (!links::GraphServiceWants(e.mode, training_episodes_)) continue;
      if (pending_.size() >= max_pending_) {
        ++surplus_;
        continue;
      }
      pending_.push_back(std::move(e));
    }
    if (!pending_.empty()) arrived_.notify_one();
  }
  arrived_.notify_all();
}

// ----------------------------------------------------------------------------- graph sink

DdsGraphSink::DdsGraphSink(const Participant& participant) : writer_(participant), status_(participant, "graph", 0) {}

void DdsGraphSink::Publish(const rl::GraphUpdate& graph) {
  if (writer_.Write(graph) != WriteResult::kSent) throw std::runtime_error("shutting down");
  spdlog::info("published graph v{}: {}", graph.version, rl::DescribeGraph(graph.graph));
}

void DdsGraphSink::PublishStatus(const rl::NodeReport& report) { status_.Publish(report); }

}  // namespace srics::transport
