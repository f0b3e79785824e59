#pragma once
// The in-process trainer: environment, policy and learner in one process, with a given
// interaction graph (or the ground-truth graph of the preset). It is the reference behaviour
// the distributed system must match: the same rollout loops, learner and rate limiter.

#include <functional>
#include <string>
#include <vector>

#include "common/config/config.h"
#include "common/rl/evaluation.h"
#include "common/rl/graph.h"

namespace srics::trainer {

// One point of the learning curve.
struct EvalPoint {
  uint64_t env_steps = 0;
  uint64_t updates = 0;
  double wall_seconds = 0;
  rl::EvaluationSummary summary;
};

struct Progress {
  uint64_t env_steps = 0;
  uint64_t total_env_steps = 0;
  uint64_t updates = 0;
  double steps_per_second = 0;
  double updates_per_second = 0;
  double alpha = 0;
  double q_loss = 0;
  const EvalPoint* last_eval = nullptr;       // null before the first evaluation
  const rl::EvaluationSummary* passive = nullptr;
};

struct TrainerOptions {
  std::string run_dir;                 // where curve.csv, curve.png, checkpoint go ("" = nowhere)
  const rl::InteractionGraph* graph = nullptr;  // null = ground truth of config.env
  std::function<void(const Progress&)> on_progress;  // called about every progress_seconds
  double progress_seconds = 5;
};

struct TrainResult {
  std::vector<EvalPoint> curve;
  rl::EvaluationSummary passive;       // the passive policy on the same evaluation goals
  uint64_t env_steps = 0;
  uint64_t updates = 0;
  uint64_t unstable_episodes = 0;
  double wall_seconds = 0;
};

// Runs a whole training run as configured (run.total_env_steps, run.max_wall_minutes,
// actors.eval_every_env_steps / eval_episodes, learner.*, agent.*).
TrainResult TrainInProcess(const config::Config& config, const TrainerOptions& options);

// Writes the curve as CSV (one row per evaluation, passive columns repeated for plotting).
void WriteCurveCsv(const std::string& path, const TrainResult& result);
// Draws curve.png from the CSV with gnuplot; returns false (and says why on stderr) when
// gnuplot is missing or fails: the CSV remains the record.
bool PlotCurve(const std::string& csv_path, const std::string& png_path, const std::string& title);

}  // namespace srics::trainer
