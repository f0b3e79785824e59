#pragma once
// The command line every role process shares:
//   PROGRAM CONFIG [--set key.path=value ...] [--run-dir DIR] [--id K] [--log-level LEVEL]
// Parsing only: mains load the config with LoadConfig(config_path, overrides).

#include <algorithm>
#include <optional>
#include <string>
#include <utility>
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

// Walks a command line one argument at a time, for the programs' own parsers:
//   for (ArgumentReader r(argc, argv); r.Next();)
//     if (r.arg() == "--out") out = r.Value(); else ...
class ArgumentReader {
 public:
  explicit ArgumentReader(std::vector<std::string> args) : args_(std::move(args)) {}
  ArgumentReader(int argc, char** argv) : args_(argv + std::min(argc, 1), argv + argc) {}

  // Moves to the next argument; false after the last.
  bool Next() { return ++at_ < args_.size(); }
  const std::string& arg() const { return args_[at_]; }
  // Takes the argument after the current option as its value; throws std::invalid_argument
  // "<option> needs a value" when there is none.
  const std::string& Value();

 private:
  std::vector<std::string> args_;
  size_t at_ = static_cast<size_t>(-1);
};

}  // namespace srics::config
