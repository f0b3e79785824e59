#pragma once
// The command line every role process shares:
//   PROGRAM CONFIG [--set key.path=value ...] [--run-dir DIR] [--id K] [--log-level LEVEL]
// Parsing only: mains load the config with LoadConfig(config_path, overrides).

#include <optional>
#include <string>
#include <vector>

namespace srics::config {

struct CommandLine {
  std::string config_path;
  std::vector<std::string> overrides;   // "key.path=value"
  std::string run_dir;                  // empty: no files (logs to the console only)
  std::optional<int> id;                // actors: which one
  std::string log_level;                // empty: the config's run.log_level
  std::vector<std::string> positional;  // anything else not starting with "--"
};

// Parses argv; throws ConfigError with a usage line on an unknown option or a missing value.
CommandLine ParseCommandLine(int argc, char** argv, const std::string& usage);

}  // namespace srics::config
