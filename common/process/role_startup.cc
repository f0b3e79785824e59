#include "common/process/role_startup.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>

#include "common/cli/cli.h"
#include "common/files/durable_file.h"
#include "common/logging/logging.h"
#include "common/process/memory.h"

namespace srics::process {

std::optional<int> ParseRoleCommandLine(int argc, char** argv, const RoleProgram& program, CommandLine* cl) {
  CLI::App app{program.description, program.program};
  cli::Configure(app);
  app.add_option("CONFIG", cl->config_path, "the run's config file (YAML)")
      ->required()
      ->transform(cli::InstalledConfig());
  cli::AddSetOption(app, &cl->overrides, "override a config value, key.path=value (repeatable)");
  app.add_option("--run-dir", cl->run_dir, "the run folder: logs, state files, checkpoints (default: none)")
      ->type_name("DIR");
  app.add_option("--log-level", cl->log_level, "trace, debug, info, warn, error (default: the config's run.log_level)")
      ->type_name("LEVEL");
  CLI::Option* id = nullptr;
  if (program.needs_id) {
    id = app.add_option_function<int>(
                "--id", [cl](int k) { cl->id = k; }, "which actor: seed, evaluator or not, log name")
             ->check(cli::Integer(0, std::numeric_limits<int>::max()));
  }
  if (const auto code = cli::Parse(app, argc, argv)) return *code;
  if (id != nullptr && !cl->id) return cli::UsageError(program.program, "--id K is required");
  return std::nullopt;
}

std::optional<int> StartRole(int argc, char** argv, const RoleProgram& program, Role* role) {
  SetUpHeap();
  if (const auto code = ParseRoleCommandLine(argc, argv, program, &role->command_line)) return code;
  try {
    role->config = config::LoadConfig(role->command_line.config_path, role->command_line.overrides);
    if (role->config.transport.run_id == config::kAutoRunId)
      throw config::ConfigError(role->command_line.config_path +
                                ": transport.run_id: expected the run's id (the same for every role of the run, "
                                "e.g. --set transport.run_id=exp7), got 'auto', which only srics run and srics "
                                "sweep resolve (they write it into the run folder's config.yaml)");
    role->name =
        program.needs_id ? program.base_name + "-" + std::to_string(*role->command_line.id) : program.base_name;
    // DDS Security: the process's own identity of the keystore, every file checked before DDS starts.
    // Its samples are accepted only from the identity named as the role (transport::SenderIdentity).
    auto& security = role->config.transport.security;
    if (!security.keystore.empty() && !security.identity.empty() && security.identity != role->name)
      throw config::ConfigError("transport.security.identity: '" + security.identity + "' cannot speak for " +
                                role->name +
                                ": under DDS Security the run accepts a role's samples only from the "
                                "keystore identity named as the role (actor-K, learner, graph); leave "
                                "transport.security.identity empty for the roles");
    security.identity = config::CheckKeystore(security, role->name);
    logging::LogOptions log;
    log.level = role->command_line.log_level.empty() ? role->config.run.log_level : role->command_line.log_level;
    if (!role->command_line.run_dir.empty() && role->config.run.log_to_file)
      log.file = role->command_line.run_dir + "/logs/" + role->name + ".log";
    logging::SetUpLogger(role->name, log);
  } catch (const std::exception& e) {
    std::cerr << program.program << ": " << e.what() << "\n";
    return kExitUsage;
  }
  return std::nullopt;
}

int RunRole(int argc, char** argv, const RoleProgram& program, const std::function<int(const Role&)>& body) {
  Role role;
  if (const auto code = StartRole(argc, argv, program, &role)) return *code;
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
