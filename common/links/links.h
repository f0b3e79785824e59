#pragma once
// The seams between the roles. Each loop (actor/ActorLoop, learner/LearnerLoop,
// graph_service/GraphService) talks to the rest of the system only through its link; the same
// loops run as separate processes over DDS (common/transport/dds_links.h) or in one process
// wired by the in-memory bus (common/links/in_memory_bus.h). Plain data only: no DDS here.
//
// Threading: every method of a link is called only from the thread that steps its loop.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/rl/episode.h"
#include "common/rl/updates.h"

namespace srics::links {

// The actor's connection to the system.
class ActorLink {
 public:
  virtual ~ActorLink() = default;
  // The newest weights with a version above `newer_than` (the version the caller uses), if any
  // (non-blocking). The caller checks them against its network and keeps its version when it
  // refuses them: a refused sample, whatever its version, never hides the next good one.
  virtual std::optional<rl::WeightsUpdate> PollWeights(uint64_t newer_than) = 0;
  // The newest graph not returned before, if any (non-blocking).
  virtual std::optional<rl::GraphUpdate> PollGraph() = 0;
  // The newest learner progress, waiting at most `wait` for news; empty if none ever came.
  virtual std::optional<rl::LearnerProgress> PollLearner(std::chrono::milliseconds wait) = 0;
  // Publishes a whole episode; false when it was not sent (the process is shutting down).
  virtual bool PublishEpisode(const rl::Episode& episode) = 0;
  virtual void PublishEval(const rl::EvalReport& report) = 0;
  virtual void PublishStatus(const rl::NodeReport& report) = 0;
};

// The learner's connection to the system.
class LearnerLink {
 public:
  virtual ~LearnerLink() = default;
  // Appends up to `max` received episodes, waiting at most `wait` for the first. Returns how
  // many were appended. Episodes the link refused (malformed, of another layout) are counted
  // by the link (rejected()) and never appended.
  virtual size_t TakeEpisodes(std::vector<rl::Episode>* out, size_t max, std::chrono::milliseconds wait) = 0;
  // The newest graph not returned before, if any (non-blocking).
  virtual std::optional<rl::GraphUpdate> PollGraph() = 0;
  // By value: the parameters (megabytes) are moved through to the wire, not copied.
  virtual void PublishWeights(rl::WeightsUpdate weights) = 0;
  virtual void PublishStats(const rl::LearnerReport& report) = 0;
  virtual void PublishStatus(const rl::NodeReport& report) = 0;
};

// Which episodes the graph service learns from: the explore episodes (random actions), and the
// agent's training episodes too when it refines its graph (graph.refine_after_publish). The one
// rule for every episode source and the service's own data set.
inline bool GraphServiceWants(rl::EpisodeMode mode, bool training_episodes) {
  return mode == rl::EpisodeMode::kExplore || (training_episodes && mode == rl::EpisodeMode::kTrain);
}

// Where the graph service's explore episodes come from.
class EpisodeSource {
 public:
  virtual ~EpisodeSource() = default;
  // Appends the episodes available now, waiting at most `timeout` for the first one.
  // Returns false once the source is closed and will never deliver again.
  // Episodes are untrusted: the service validates each one and counts what it drops.
  virtual bool Poll(std::chrono::milliseconds timeout, std::vector<rl::Episode>* out) = 0;
};

// Where the graph service's graphs and status go.
class GraphSink {
 public:
  virtual ~GraphSink() = default;
  // Publishes a graph (the InteractionGraph topic: transient-local, keep-last 1). Versions
  // increase across publications. May throw; the service logs and retries later.
  virtual void Publish(const rl::GraphUpdate& graph) = 0;
  virtual void PublishStatus(const rl::NodeReport& report) = 0;
};

}  // namespace srics::links
