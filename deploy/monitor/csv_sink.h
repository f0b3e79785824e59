#pragma once
// Appends received samples to eval.csv, learner.csv and nodes.csv in one folder, one row per
// sample, flushed at once (so `tail -f` and scripts see rows as they arrive). A file that is
// new or empty gets a header first; an existing one is appended to (a restarted monitor or
// launcher continues the same files).
//
// Columns (wall_time is Unix time in seconds; per-entity vectors are ';'-joined in one field):
//   eval.csv     wall_time,run_id,actor_id,policy_version,graph_version,env_steps,episodes,
//                avg_distance,avg_object_distance,success_rate,selectivity,entity_distance,
//                subgoal_success,independent_solved,independent_undone
//                (the last two summed over the evaluation's attempts: solved objects an attempt
//                began with that are not its entity's ancestors, and how many it undid; files
//                written before 2026-12-04 end at subgoal_success)
//   learner.csv  wall_time,run_id,updates,transitions_inserted,replay_size,episodes_accepted,
//                episodes_rejected,policy_version,q_loss,policy_loss,alpha,entropy,
//                updates_per_second,inserts_per_second,mean_reward
//   nodes.csv    wall_time,run_id,role,node_id,host,pid,state,policy_version,graph_version,
//                env_steps,dropped_samples,uptime_ms,detail
//                (state is the node's own state, or "lost" / "exited" when the monitor saw it go)

#include <fstream>
#include <string>

#include "common/transport/messages.h"

namespace srics::monitor {

class CsvSink {
 public:
  // Creates `dir` if needed and opens the three files. Throws std::runtime_error naming the file.
  explicit CsvSink(const std::string& dir);

  void Append(const transport::EvalResult& result, double wall_time);
  void Append(const transport::LearnerStats& stats, double wall_time);
  // `state_override` replaces the state column when not empty ("lost", "exited").
  void Append(const transport::NodeStatus& status, double wall_time, const std::string& state_override = "");

  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  std::ofstream eval_;
  std::ofstream learner_;
  std::ofstream nodes_;
};

// A CSV field of a peer's string: PrintableText (no control characters, so no line breaks),
// quoted (with doubled quotes) when it holds a comma or quote.
std::string CsvField(const std::string& text);

// Seconds since the Unix epoch, now.
double WallTimeNow();

}  // namespace srics::monitor
