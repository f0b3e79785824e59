#pragma once
// The command line of `srics`: its subcommands (run, sweep, compare, eval, learn-graph) and
// their options, on the one parser of every program (common/cli, CLI11). Every option of
// every subcommand is declared here, next to its help text: to add one, add a field to the
// subcommand's options struct (launcher.h, sweep.h, ...) and one line below in
// command_line.cc. `srics --help` and `srics SUBCOMMAND --help` list them.

#include <optional>
#include <string>
#include <vector>

#include "deploy/analysis/column.h"
#include "deploy/analysis/compare.h"
#include "deploy/eval/eval.h"
#include "deploy/launcher/in_process_run.h"
#include "deploy/launcher/launcher.h"
#include "deploy/launcher/sweep.h"

namespace srics::launcher {

// One parsed `srics` command line: which subcommand, and its options.
struct SricsCommand {
  enum class Kind { kRun, kSweep, kCompare, kEval, kLearnGraph, kColumn };
  Kind kind = Kind::kRun;
  std::string name;  // "srics run": what messages start with
  LaunchOptions run;
  SweepOptions sweep;
  analysis::CompareOptions compare;
  eval::EvalArgs eval;
  LearnGraphOptions learn_graph;
  analysis::ColumnOptions column;
};

// Parses argv into *command. Returns nothing when the program goes on; else its exit code
// after printing the help or the version (0) or what is wrong, naming the argument (2).
std::optional<int> ParseSricsCommandLine(int argc, char** argv, SricsCommand* command);

// The arguments after `srics run`, `srics sweep`, ... (tests and the sweep's own checks);
// throw std::invalid_argument naming the argument.
LaunchOptions ParseRunArgs(const std::vector<std::string>& args);
SweepOptions ParseSweepArgs(const std::vector<std::string>& args);
analysis::CompareOptions ParseCompareArgs(const std::vector<std::string>& args);
eval::EvalArgs ParseEvalArgs(const std::vector<std::string>& args);
LearnGraphOptions ParseLearnGraphArgs(const std::vector<std::string>& args);

}  // namespace srics::launcher
