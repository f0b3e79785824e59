#include "common/process/role_startup.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "common/files/durable_file.h"
#include "common/logging/logging.h"

namespace srics::process {

std::string UsageOf(const RoleProgram& program) {
  return program.program + (program.needs_id ? " CONFIG --id K" : " CONFIG") +
         " [--set key.path=value ...] [--run-dir DIR] [--log-level LEVEL]";
}

int StartRole(int argc, char** argv, const RoleProgram& program, Role* role) {
  const std::string usage = UsageOf(program);
  try {
    role->command_line = config::ParseCommandLine(argc, argv, usage);
    if (program.needs_id && !role->command_line.id)
      throw config::ConfigError("--id K is required\nusage: " + usage);
    role->config = config::LoadConfig(role->command_line.config_path, role->command_line.overrides);
    if (role->config.transport.run_id == config::kAutoRunId)
      throw config::ConfigError(role->command_line.config_path +
                                ": transport.run_id: expected the run's id (the same for every role of the run, "
                                "e.g. --set transport.run_id=exp7), got 'auto', which only srics run and srics "
                                "sweep resolve (they write it into the run folder's config.yaml)");
    role->name = program.needs_id ? program.base_name + "-" + std::to_string(*role->command_line.id)
                                  : program.base_name;
    // DDS Security: the process's own identity of the keystore, every file checked before DDS starts
    role->config.transport.security.identity = config::CheckKeystore(role->config.transport.security, role->name);
    logging::LogOptions log;
    log.level = role->command_line.log_level.empty() ? role->config.run.log_level : role->command_line.log_level;
    if (!role->command_line.run_dir.empty() && role->config.run.log_to_file)
      log.file = role->command_line.run_dir + "/logs/" + role->name + ".log";
    logging::SetUpLogger(role->name, log);
  } catch (const std::exception& e) {
    std::cerr << program.program << ": " << e.what() << "\n";
    return kExitConfig;
  }
  return 0;
}

int RunRole(int argc, char** argv, const RoleProgram& program,
            const std::function<int(const Role&)>& body) {
  Role role;
  if (const int code = StartRole(argc, argv, program, &role)) return code;
  try {
    return body(role);
  } catch (const UnusableStateError& e) {
    spdlog::critical("{} cannot start: {}", role.name, e.what());
    return kExitUnusableState;
  } catch (const std::exception& e) {
    spdlog::critical("{} failed: {}", role.name, e.what());
    return 1;
  }
}

uint64_t NextActorFirstEpisodeId(const std::string& run_dir, const std::string& name) {
  if (run_dir.empty()) return 0;
  std::filesystem::create_directories(run_dir + "/state");
  const std::string path = run_dir + "/state/" + name + ".generation";
  uint64_t generation = 0;
  std::ifstream(path) >> generation;
  // durable: a count lost in a crash would repeat the episode ids (and seeds) of a generation
  files::WriteFileDurably(path, std::to_string(generation + 1) + "\n");
  return generation << 32;
}

}  // namespace srics::process
