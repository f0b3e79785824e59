#pragma once
// The learner's loop, with no transport in it: ingest whole episodes, follow the graph,
// update at the configured ratio, publish weights every K updates and stats, checkpoint, and
// stop once the run's budget of environment steps is in and trained on. It talks to the rest
// of the system only through a links::LearnerLink: DDS in the srics-learner process, the
// in-memory bus in `srics run --in-process`.
//
//   LearnerLoop loop(LearnerLoopOptionsFor(config, rl::RunShapeFor(config), run_dir + "/checkpoint.srics"), &link);
//   loop.Run(stop);                       // or: while (loop.Step() != StepResult::kDone)

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/config/config.h"
#include "common/links/links.h"
#include "common/logging/logging.h"
#include "learner/episode_dedup.h"
#include "learner/learner.h"
#include "learner/training_log.h"

namespace srics::learner {

struct LearnerLoopOptions {
  LearnerOptions learner;
  int num_entities = 0;  // of the run's environment: graphs of another size are refused
  // empty: no checkpoints (and no <path>.versions, see ReserveVersions). Written every
  // learner.checkpoint_every_updates updates and at the end, keeping learner.keep_checkpoints
  // generations (path, path.1, ...). At start the newest readable one is loaded: a corrupt one
  // (truncated, checksum) is set aside as <file>.corrupt with an error naming it and what is
  // wrong, and the next older one is tried.
  std::string checkpoint_path;
  files::FileSystem* file_system = &files::FileSystem::Posix();  // tests inject failures here
  int max_updates_per_step = 8;  // updates between two looks at the link (responsiveness)
  // only the updates the data already pays for (learner.updates_per_step), none ahead into the
  // rate limiter's error buffer until the budget is in (the two-thread in-process run)
  bool updates_on_ratio_only = false;
  // stats and status this often; 0: after every step (the in-process run, so that actors see
  // exact progress and the run is deterministic)
  double report_period_s = 1;
  // after the final weights, wait this long before the budget-done stats (DDS delivers the
  // two topics independently: actors should have the final weights when they see the end)
  std::chrono::milliseconds final_weights_grace{300};
  // train.csv: figures of the training episodes (selectivity during training) per evaluation
  // interval; LearnerLoopOptionsFor puts it beside the checkpoint
  TrainingLogOptions training_log;
  int rejected_log_interval_s = 5;  // refused episodes and graphs, skipped updates: logged this often
};

LearnerLoopOptions LearnerLoopOptionsFor(const config::Config& config, const rl::RunShape& shape,
                                         std::string checkpoint_path);

enum class StepResult { kWorked, kIdle, kDone };

// Thrown by Step when learner.max_skipped_updates_in_a_row updates in a row met a non-finite
// value: the networks no longer change, so the run ends instead of training on unchanged.
class LearningDivergedError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class LearnerLoop {
 public:
  LearnerLoop(LearnerLoopOptions options, links::LearnerLink* link);

  // Loads the newest usable checkpoint (if any) and publishes the first weights. Called by
  // the first Step. Throws nn::CheckpointError when no checkpoint can be loaded though the run
  // has some (every generation corrupt or set aside before, or one of another architecture):
  // a learner never silently starts from scratch over a run's checkpoint.
  void Start();
  // Takes episodes (waiting at most `wait` when there is no update to do), follows the
  // graph, does the updates the rate limiter allows (at most max_updates_per_step), publishes
  // and checkpoints when due. kDone once the budget is in and trained on (final weights,
  // checkpoint and stats are out then). Throws LearningDivergedError (see there).
  StepResult Step(std::chrono::milliseconds wait = std::chrono::milliseconds(0));
  // Final weights, checkpoint and stats. Called by Step at the end of the budget and by Run
  // when stopped.
  void Finish();
  // Steps until `stop` or the end of the budget; returns 0.
  int Run(const std::atomic<bool>& stop);

  Learner& learner() { return learner_; }
  uint64_t graphs_rejected() const { return graphs_rejected_; }
  // Episodes refused because this learner had stored them before (EpisodeDedup; the restored
  // replay's count as stored). NodeStatus: "episode.duplicate".
  uint64_t duplicates_refused() const { return duplicates_; }
  // Weights not published because a parameter was not finite or beyond rl::kMaxAbsParameter.
  uint64_t weights_withheld() const { return weights_withheld_; }
  uint64_t graph_version() const { return graph_version_; }

 private:
  void Publish();
  void Report(bool force);
  void FollowGraph();
  void LoadNewestCheckpoint();
  void SaveCheckpoint();
  // Policy versions are reserved durably a block at a time (<checkpoint>.versions) before one
  // of the block is published; a new start continues above the reservation, so a version is
  // never published twice, whatever checkpoint the start resumes from (or none).
  static constexpr uint64_t kVersionBlock = 64;
  std::string VersionsPath() const;
  void ReserveVersions(uint64_t version);
  void ContinueVersions();
  uint64_t versions_reserved_ = 0;

  LearnerLoopOptions options_;
  links::LearnerLink* link_;
  Learner learner_;
  bool started_ = false;
  bool finished_ = false;
  UpdateStats last_update_;
  uint64_t graph_version_ = 0;
  uint64_t graphs_rejected_ = 0;
  EpisodeDedup seen_;
  uint64_t duplicates_ = 0;
  uint64_t weights_withheld_ = 0;
  std::unique_ptr<logging::RateLimiter> refusals_log_;
  uint64_t checkpointed_at_ = 0;
  uint64_t checkpoint_failures_ = 0;
  std::vector<rl::Episode> episodes_;
  TrainingLog training_log_;
  std::chrono::steady_clock::time_point last_report_, rate_window_start_;
  uint64_t updates_at_window_ = 0, inserted_at_window_ = 0;
  double updates_per_second_ = 0, inserts_per_second_ = 0;
};

}  // namespace srics::learner
