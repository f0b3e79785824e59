#include "common/process/role_startup.h"

#include <iostream>

#include "common/logging/logging.h"

namespace srics::process {

int StartRole(int argc, char** argv, const std::string& program, const std::string& usage,
              const std::string& base_name, bool needs_id, Role* role) {
  try {
    role->command_line = config::ParseCommandLine(argc, argv, usage);
    if (needs_id && !role->command_line.id)
      throw config::ConfigError("--id K is required\nusage: " + usage);
    role->config = config::LoadConfig(role->command_line.config_path, role->command_line.overrides);
    role->name = needs_id ? base_name + "-" + std::to_string(*role->command_line.id) : base_name;
    logging::LogOptions log;
    log.level = role->command_line.log_level.empty() ? role->config.run.log_level : role->command_line.log_level;
    if (!role->command_line.run_dir.empty() && role->config.run.log_to_file)
      log.file = role->command_line.run_dir + "/logs/" + role->name + ".log";
    logging::SetUpLogger(role->name, log);
  } catch (const std::exception& e) {
    std::cerr << program << ": " << e.what() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace srics::process
