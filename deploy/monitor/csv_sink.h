#pragma once
// Appends received samples to eval.csv, learner.csv and nodes.csv in one folder, one row per
// sample, flushed at once (so `tail -f` and scripts see rows as they arrive). A file that is
// new or empty gets a header first; an existing one is appended to (a restarted monitor or
// launcher continues the same files).
//
// Columns: deploy/run_folder/schema.h.

#include <fstream>
#include <string>

#include "common/rl/updates.h"
#include "common/transport/wire.h"

namespace srics::monitor {

class CsvSink {
 public:
  // Creates `dir` if needed and opens the three files. Throws std::runtime_error naming the file.
  explicit CsvSink(const std::string& dir);

  void Append(const std::string& run_id, const rl::EvalReport& result, double wall_time);
  void Append(const std::string& run_id, const rl::LearnerReport& stats, double wall_time);
  // `state_override` replaces the state column when not empty ("lost", "exited").
  void Append(const std::string& run_id, const rl::NodeStatus& status, double wall_time,
              const std::string& state_override = "");

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
