#pragma once
// The start every role process shares (srics-actor, srics-learner, srics-graph): parse the
// command line, load and validate the config, set up the role's logger (console, and a file
// in the run folder's logs/ when there is one), then run the role and log what ended it.

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

#include <vector>
#include "common/cli/exit_codes.h"

#include "common/config/config.h"

namespace srics::process {

// The command line every role process shares:
//   PROGRAM CONFIG [--set key.path=value ...] [--run-dir DIR] [--id K] [--log-level LEVEL]
struct CommandLine {
  std::string config_path;
  std::vector<std::string> overrides;  // "key.path=value"
  std::string run_dir;                 // empty: no files (logs to the console only)
  std::optional<int> id;               // actors: which one
  std::string log_level;               // empty: the config's run.log_level
};

// Exit codes of the role programs: common/cli/exit_codes.h (kExitUsage for a bad command line
// or config, kExitUnusableState for an UnusableStateError).

// Thrown by a role body when its state on disk cannot be used and a restart cannot help:
// RunRole logs it and exits with kExitUnusableState.
class UnusableStateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Role {
  CommandLine command_line;
  config::Config config;
  std::string name;  // logger and log-file name: "learner", "graph", "actor-3"
};

// What distinguishes one role program from another at start-up.
struct RoleProgram {
  std::string program;      // "srics-actor"
  std::string base_name;    // "actor"
  bool needs_id = false;    // --id K required, appended to the name ("actor-3")
  std::string description;  // the first line of --help
};

// Parses a role program's command line (argv[0] is the program). Returns nothing when the
// program goes on; else the exit code after printing the help or the version (0) or what is
// wrong with the arguments, naming the argument (kExitUsage).
std::optional<int> ParseRoleCommandLine(int argc, char** argv, const RoleProgram& program, CommandLine* command_line);

// Fills *role and returns nothing; or returns the exit code of the program: 0 after printing
// --help or --version, kExitUsage after printing "<program>: <what is wrong>" to stderr when
// the command line, the config or the log level is bad.
std::optional<int> StartRole(int argc, char** argv, const RoleProgram& program, Role* role);

// StartRole, then body(role) (not after --help or --version: exit 0); an exception out of the body is logged as "<name>
// failed: ..." and gives exit code 1 (kExitUnusableState for an UnusableStateError). Returns the exit code of the
// process.
int RunRole(int argc, char** argv, const RoleProgram& program, const std::function<int(const Role&)>& body);

// The first episode id of an actor starting in the run folder `run_dir` (in its own process
// or in process): a small state file, <run_dir>/state/<name>.generation, counts the actor's
// starts in that folder, so the episode ids of a restarted or resumed actor keep increasing
// (generation << 32; its episodes' seeds then differ from the earlier ones). 0 without a run
// folder.
uint64_t NextActorFirstEpisodeId(const std::string& run_dir, const std::string& name);

}  // namespace srics::process
