#pragma once
// The start every role process shares (srics-actor, srics-learner, srics-graph): parse the
// command line, load and validate the config, set up the role's logger (console, and a file
// in the run folder's logs/ when there is one).

#include <string>

#include "common/config/command_line.h"
#include "common/config/config.h"

namespace srics::process {

struct Role {
  config::CommandLine command_line;
  config::Config config;
  std::string name;  // logger and log-file name: "learner", "graph", "actor-3"
};

// Fills *role and returns 0, or prints "<program>: <what is wrong>" to stderr and returns the
// exit code (2) when the command line, the config or the log level is bad. `base_name` is
// the role ("actor"); with `needs_id` the --id option is required and appended ("actor-3").
int StartRole(int argc, char** argv, const std::string& program, const std::string& usage,
              const std::string& base_name, bool needs_id, Role* role);

}  // namespace srics::process
