#pragma once
// The actor process's loop without DDS: explore at random until a graph (for methods that
// use one) and first weights exist, then run training episodes on independently
// controllable subgoals with the latest weights (taken between episodes), waiting when the
// learner is too far behind; designated actors evaluate on a schedule. The main supplies an
// ActorLink over DDS; tests may supply another.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "common/config/config.h"
#include "common/rl/episode.h"
#include "common/rl/updates.h"

namespace srics::actor {

// The actor's connection to the system. Only called from the thread running ActorLoop::Run.
class ActorLink {
 public:
  virtual ~ActorLink() = default;
  // The newest weights not returned before, if any (non-blocking).
  virtual std::optional<rl::WeightsUpdate> PollWeights() = 0;
  // The newest graph not returned before, if any (non-blocking).
  virtual std::optional<rl::GraphUpdate> PollGraph() = 0;
  // The newest learner progress, waiting at most `wait` for news; empty if none ever came.
  virtual std::optional<rl::LearnerProgress> PollLearner(std::chrono::milliseconds wait) = 0;
  // Publishes a whole episode; false when the process is shutting down (not sent).
  virtual bool PublishEpisode(const rl::Episode& episode) = 0;
  virtual void PublishEval(const rl::EvalReport& report) = 0;
  virtual void PublishStatus(const rl::NodeReport& report) = 0;
};

struct ActorCounters {
  uint64_t env_steps = 0;
  uint64_t episodes = 0;
  uint64_t unstable_episodes = 0;
  uint64_t weights_rejected = 0;   // wrong architecture or size
  uint64_t graphs_rejected = 0;    // graph does not fit this environment
  uint64_t evaluations = 0;
  uint64_t waits = 0;              // times the rate limiter held the actor back
};

class ActorLoop {
 public:
  // `first_episode_id` lets a restarted actor continue its episode numbering.
  ActorLoop(const config::Config& config, uint32_t actor_id, ActorLink* link,
            uint64_t first_episode_id = 0);
  ~ActorLoop();

  // Runs until `stop` or until the learner reports the run's budget done (after a final
  // evaluation on evaluating actors). Returns 0 on a clean end.
  int Run(const std::atomic<bool>& stop);

  const ActorCounters& counters() const { return counters_; }
  uint64_t next_episode_id() const { return next_episode_id_; }

 private:
  struct State;
  std::unique_ptr<State> state_;
  config::Config config_;
  uint32_t actor_id_;
  ActorLink* link_;
  uint64_t next_episode_id_;
  ActorCounters counters_;
};

}  // namespace srics::actor
