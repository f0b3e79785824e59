#pragma once
// How a run ended, in <dir>/outcome.yaml: written when a run stops in any way but a kill of
// the launcher itself ("finished", "interrupted" or "failed", the exit code, the reason) and
// removed when a run starts in the folder, so a folder without it holds a run that is going on
// or was killed. `srics sweep` takes a run as done when it says "finished".

#include <optional>
#include <string>

namespace srics::run_folder {

struct RunOutcome {
  std::string state;
  int exit_code = 0;
  std::string reason;
  // CPU seconds of this launch: srics run and every process it started (a resumed run's
  // earlier launches not included); negative: not known (a folder written before it was kept)
  double cpu_seconds = -1;
};
void WriteRunOutcome(const std::string& dir, const RunOutcome& outcome);
// Empty when there is no readable outcome.yaml.
std::optional<RunOutcome> ReadRunOutcome(const std::string& dir);
void RemoveRunOutcome(const std::string& dir);
// Whether the run in `dir` finished (its outcome.yaml says so).
bool RunFinished(const std::string& dir);

// `text` as a double-quoted YAML/JSON string (backslash escapes; other control characters as
// spaces), and back (text that is not quoted is returned as it is).
std::string QuotedString(const std::string& text);
std::string UnquotedString(const std::string& text);

}  // namespace srics::run_folder
