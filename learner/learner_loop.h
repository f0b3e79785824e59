#pragma once
// The learner process's loop without DDS: ingest whole episodes, follow the graph, update at
// the configured ratio, publish weights every K updates and stats periodically, checkpoint,
// and stop once the run's budget of environment steps is in and trained on. The main
// supplies a LearnerLink over DDS.

#include <atomic>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "common/config/config.h"
#include "common/rl/episode.h"
#include "common/rl/updates.h"
#include "learner/learner.h"

namespace srics::learner {

struct LearnerReport {
  LearnerCounters counters;
  uint64_t replay_size = 0;
  uint64_t episodes_rejected = 0;
  UpdateStats last_update;
  double updates_per_second = 0;
  double inserts_per_second = 0;  // transitions
};

// Only called from the thread running LearnerLoop::Run.
class LearnerLink {
 public:
  virtual ~LearnerLink() = default;
  // Appends up to `max` episodes, waiting at most `wait` for the first. Returns how many.
  virtual size_t TakeEpisodes(std::vector<rl::Episode>* out, size_t max, std::chrono::milliseconds wait) = 0;
  // The newest graph not returned before, if any.
  virtual std::optional<rl::GraphUpdate> PollGraph() = 0;
  virtual void PublishWeights(const rl::WeightsUpdate& weights) = 0;
  virtual void PublishStats(const LearnerReport& report) = 0;
  virtual void PublishStatus(const rl::NodeReport& report) = 0;
};

struct LearnerLoopOptions {
  std::string checkpoint_path;  // empty: no checkpoints; loaded at start if the file exists
  int max_updates_per_poll = 8; // updates between two polls of the network (responsiveness)
};

class LearnerLoop {
 public:
  LearnerLoop(const config::Config& config, LearnerLink* link, LearnerLoopOptions options);
  // Runs until `stop` (returns 0 after a final checkpoint) or the budget is done (returns 0).
  // Throws nn::CheckpointError when an existing checkpoint cannot be loaded: a learner never
  // silently starts from scratch over a run's checkpoint.
  int Run(const std::atomic<bool>& stop);
  Learner& learner() { return learner_; }

 private:
  void Publish();
  void Report(bool force);

  config::Config config_;
  LearnerLink* link_;
  LearnerLoopOptions options_;
  Learner learner_;
  UpdateStats last_update_;
  uint64_t graph_version_ = 0;
  std::chrono::steady_clock::time_point last_report_;
  uint64_t updates_at_report_ = 0, inserted_at_report_ = 0;
};

}  // namespace srics::learner
