#include "deploy/launcher/launcher.h"

#include <unistd.h>

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <spdlog/sinks/sink.h>

#include "common/config/command_line.h"
#include "common/config/config.h"
#include "common/logging/logging.h"
#include "common/process/role_startup.h"
#include "common/transport/transport.h"
#include "deploy/dashboard/server.h"
#include "deploy/launcher/in_process_run.h"
#include "deploy/launcher/run_folder.h"
#include "deploy/launcher/run_session.h"
#include "deploy/launcher/stall_watch.h"
#include "deploy/monitor/display.h"
#include "deploy/monitor/monitor.h"

namespace srics::launcher {

DisplayMode ParseDisplayMode(const std::string& mode) {
  if (mode == "auto") return DisplayMode::kAuto;
  if (mode == "live") return DisplayMode::kLive;
  if (mode == "plain") return DisplayMode::kPlain;
  if (mode == "none") return DisplayMode::kNone;
  throw std::invalid_argument("--display expects auto, live, plain or none, got '" + mode + "'");
}

namespace tr = srics::transport;
namespace mon = srics::monitor;
namespace fs = std::filesystem;

const char* const kRunUsage =
    "usage: srics run CONFIG [--in-process] [--actors N] [--set key.path=value ...] [--run-dir DIR] [--bin-dir DIR]\n"
    "                 [--display auto|live|plain|none] [--stop-timeout S] [--final-eval-grace S]\n"
    "  CONFIG          the run's config (e.g. deploy/configs/default.yaml)\n"
    "  --in-process    the same loops in one process and one thread, wired in memory (no DDS):\n"
    "                  deterministic, the same run folder\n"
    "  --actors N      actor processes (default: actors.count of the config)\n"
    "  --set K=V       override a config value (recorded in the run folder's config.yaml)\n"
    "  --run-dir DIR   the run folder (default <run.output_dir>/<run.name>-<timestamp>); an existing\n"
    "                  one is continued: the learner resumes from its checkpoint, with the same config\n"
    "  --allow-config-change  continue a run folder with a changed config (the change is recorded\n"
    "                  in its config-changes.log, the old config.yaml kept beside it)\n"
    "  --bin-dir DIR   where srics-graph, srics-learner, srics-actor are (default: the build tree\n"
    "                  this program belongs to)\n"
    "  --display M     live (refreshing screen), plain (a line every 10 s), none, auto (live on a terminal)\n"
    "  --stop-timeout S      seconds between SIGINT and SIGKILL when stopping (default 15)\n"
    "  --final-eval-grace S  once the learner finished, wait this long for the actors' final\n"
    "                        evaluation and exit before stopping them (default 180)\n"
    "  --label TEXT    shown in the display's title (srics sweep: which run of how many)\n"
    "  --http PORT     serve the live web dashboard on PORT (127.0.0.1 only unless --http-bind)\n"
    "  --http-bind A   the address to serve it on (default 127.0.0.1; 0.0.0.0 = every interface)\n"
    "the run folder's outcome.yaml says how the run ended (finished, interrupted, failed)\n"
    "exit codes: 0 run finished, 1 a role failed for good, 2 bad arguments/config, 130 interrupted\n";

namespace {

double ParseNumber(const std::string& flag, const std::string& text, double min) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(value >= min))
    throw std::invalid_argument(flag + " expects a number >= " + std::to_string(static_cast<int>(min)) +
                                ", got '" + text + "'");
  return value;
}

// The launcher's view of its children for the display.
std::vector<mon::ProcessRow> ProcessRows(const Supervisor& supervisor, SteadyClock::time_point now) {
  std::vector<mon::ProcessRow> rows;
  for (size_t i = 0; i < supervisor.size(); ++i) {
    const ChildStatus& s = supervisor.status(i);
    mon::ProcessRow row;
    row.name = s.name;
    row.pid = s.pid;
    row.state = ChildPhaseName(s.phase);
    if (s.phase == ChildPhase::kWaitingToRestart) {
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "restarting in %.1fs",
                    std::max(0.0, std::chrono::duration<double>(s.restart_at - now).count()));
      row.state = buffer;
    }
    row.restarts = s.restarts;
    if (s.last_exit) row.last_exit = s.last_exit->Describe();
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

LaunchOptions ParseRunArgs(const std::vector<std::string>& args) {
  LaunchOptions options;
  for (config::ArgumentReader r(args); r.Next();) {
    const std::string& arg = r.arg();
    auto value = [&r]() -> const std::string& { return r.Value(); };
    if (arg == "--set") options.overrides.push_back(value());
    else if (arg == "--actors") options.actors = static_cast<int>(ParseNumber(arg, value(), 1));
    else if (arg == "--run-dir") options.run_dir = value();
    else if (arg == "--bin-dir") options.bin_dir = value();
    else if (arg == "--stop-timeout") options.stop_timeout_s = ParseNumber(arg, value(), 0);
    else if (arg == "--final-eval-grace") options.final_eval_grace_s = ParseNumber(arg, value(), 0);
    else if (arg == "--in-process") options.in_process = true;
    else if (arg == "--label") options.label = value();
    else if (arg == "--allow-config-change") options.allow_config_change = true;
    else if (arg == "--http") options.http_port = dashboard::ParseHttpPort(value());
    else if (arg == "--http-bind") options.http_bind = value();
    else if (arg == "--display") {
      options.display = ParseDisplayMode(value());
    } else if (!arg.empty() && arg[0] == '-') {
      throw std::invalid_argument("unknown option " + arg);
    } else if (options.config_file.empty()) {
      options.config_file = arg;
    } else {
      throw std::invalid_argument("unexpected argument " + arg);
    }
  }
  if (options.config_file.empty()) throw std::invalid_argument("missing CONFIG");
  if (options.http_port < 0 && options.http_bind != "127.0.0.1")
    throw std::invalid_argument("--http-bind needs --http PORT");
  if (options.actors > 0) options.overrides.push_back("actors.count=" + std::to_string(options.actors));
  return options;
}

namespace {

// The role processes of one run under a supervisor.
struct Roles {
  size_t graph = 0, learner = 0;
  std::vector<size_t> actors;
};

Roles AddRoles(Supervisor* supervisor, const LaunchOptions& options, const config::Config& config,
               const std::string& dir) {
  const std::string graph_bin = FindProgram("srics-graph", "graph_service", options.bin_dir);
  const std::string learner_bin = FindProgram("srics-learner", "learner", options.bin_dir);
  const std::string actor_bin = FindProgram("srics-actor", "actor", options.bin_dir);
  auto argv = [&](const std::string& bin, std::vector<std::string> extra) {
    std::vector<std::string> v = {bin, dir + "/config.yaml", "--run-dir", dir};
    v.insert(v.end(), extra.begin(), extra.end());
    return v;
  };
  // a role that exits with 2 (config) or 65 (unusable state on disk) fails the run at once
  const std::vector<int> finals = {process::kExitConfig, process::kExitUnusableState};
  Roles roles;
  roles.graph = supervisor->Add({.name = "graph", .argv = argv(graph_bin, {}), .output_file = dir + "/logs/graph.out",
                                 .max_restarts = options.max_restarts_service, .final_exit_codes = finals});
  roles.learner = supervisor->Add({.name = "learner", .argv = argv(learner_bin, {}),
                                   .output_file = dir + "/logs/learner.out", .max_restarts = options.max_restarts_service,
                                   .final_exit_codes = finals});
  for (int k = 0; k < config.actors.count; ++k)
    roles.actors.push_back(supervisor->Add({.name = "actor-" + std::to_string(k),
                                            .argv = argv(actor_bin, {"--id", std::to_string(k)}),
                                            .output_file = dir + "/logs/actor-" + std::to_string(k) + ".out",
                                            .final_exit_codes = finals}));
  return roles;
}

// Why the run ends now (empty: it goes on), from the children's phases and the clock.
struct Ending {
  std::string reason;
  int exit_code = kExitDone;
};

class EndWatch {
 public:
  EndWatch(const LaunchOptions& options, const config::Config& config, const Roles& roles)
      : options_(options), config_(config), roles_(roles) {}

  Ending Check(Supervisor& supervisor, RunSession& session) {
    for (size_t i : supervisor.Tick()) {
      const ChildStatus& s = supervisor.status(i);
      if (i == roles_.learner && s.phase == ChildPhase::kFinished) {
        learner_done_ = SteadyClock::now();
        session.Event("the learner finished its budget; waiting for the actors' final evaluation");
      } else if ((i == roles_.learner || i == roles_.graph) && s.phase == ChildPhase::kFailed) {
        return {s.name + " failed for good (" + (s.last_exit ? s.last_exit->Describe() : "?") + ")", kExitFailed};
      }
    }
    bool actors_down = true, actor_failed = false;
    for (size_t i : roles_.actors) {
      const ChildPhase phase = supervisor.status(i).phase;
      actors_down &= phase != ChildPhase::kRunning && phase != ChildPhase::kWaitingToRestart;
      actor_failed |= phase == ChildPhase::kFailed;
    }
    const auto now = SteadyClock::now();
    const auto grace = std::chrono::duration<double>(options_.final_eval_grace_s);
    if (actors_down && !actors_down_at_) actors_down_at_ = now;
    if (learner_done_ && actors_down)
      return actor_failed ? Ending{"the budget is done, but actors failed", kExitFailed} : Ending{"the budget is done"};
    if (learner_done_ && now - *learner_done_ >= grace)
      return {"the budget is done (actors did not finish within the grace period)"};
    if (!learner_done_ && !roles_.actors.empty() && actors_down && now - *actors_down_at_ >= grace)
      return {"every actor ended but the learner did not finish", kExitFailed};
    return {WallLimitReason(config_, session.elapsed_s())};
  }


 private:
  const LaunchOptions& options_;
  const config::Config& config_;
  const Roles& roles_;
  std::optional<SteadyClock::time_point> learner_done_;   // the learner exited with 0
  std::optional<SteadyClock::time_point> actors_down_at_;  // no actor running or restarting
};

int RunProcesses(const LaunchOptions& options, const config::Config& config) {
  RunSession session(options, config);
  const std::string& dir = session.dir();
  SeedGraphFile(config, dir);  // a given graph is re-published by srics-graph
  // what the processes publish, to the display and to eval.csv, learner.csv, nodes.csv
  tr::Participant participant(config.transport);
  mon::Monitor monitor(participant, {.all_runs = false, .weights = true, .csv_dir = dir, .csv_node_statuses = true});

  SupervisorOptions supervisor_options;
  supervisor_options.backoff = options.backoff;
  supervisor_options.stop_timeout = std::chrono::milliseconds(static_cast<int64_t>(options.stop_timeout_s * 1000));
  supervisor_options.on_event = [&](const std::string& text) { session.Event(text); };
  Supervisor supervisor(supervisor_options);
  const Roles roles = AddRoles(&supervisor, options, config, dir);
  try {
    supervisor.StartAll();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    std::cerr << "srics run: " << e.what() << "\n";
    return kExitFailed;
  }

  EndWatch watch(options, config, roles);
  std::vector<WatchedNode> watched = {{roles.graph, "graph", 0}, {roles.learner, "learner", 0}};
  for (size_t k = 0; k < roles.actors.size(); ++k) watched.push_back({roles.actors[k], "actor", static_cast<uint32_t>(k)});
  StallWatch stalls(std::chrono::milliseconds(static_cast<int64_t>(config.transport.stalled_node_restart_s * 1000)),
                    config.transport.run_id, std::move(watched));
  Ending ending;
  while (ending.reason.empty()) {
    if (participant.shutdown_requested()) {
      ending = {"interrupted", kExitInterrupted};
      break;
    }
    monitor.Poll(std::chrono::milliseconds(200));
    for (const std::string& text : monitor.TakeNodeEvents()) session.Note(text);  // the monitor logged it
    ending = watch.Check(supervisor, session);
    for (const auto& [child, why] : stalls.Check(supervisor, monitor.state(), SteadyClock::now()))
      supervisor.Kill(child, why);
    if (ending.reason.empty())
      session.Show(monitor.state(), ProcessRows(supervisor, SteadyClock::now()), supervisor.total_restarts());
  }
  session.Event("stopping: " + ending.reason);
  const bool clean = supervisor.StopAll();
  monitor.Poll(std::chrono::milliseconds(0));  // what the roles said last
  return session.Finish(monitor.state(), ProcessRows(supervisor, SteadyClock::now()), ending.reason, ending.exit_code,
                        clean, supervisor.total_restarts());
}

}  // namespace

int Run(const LaunchOptions& options) {
  // config first: a bad one stops everything before a folder or a process exists
  config::Config config = config::LoadConfig(options.config_file, options.overrides);
  if (config.transport.run_id == config::kAutoRunId) {
    // this launch's own run id (or the one the folder recorded), written into the run
    // folder's config.yaml with the rest of the effective configuration; in process there is
    // no DDS to share, and a fixed id keeps eval.csv the same from launch to launch
    std::vector<std::string> overrides = options.overrides;
    overrides.push_back("transport.run_id=" + (options.in_process ? std::string("in-process") : ChooseRunId(options.run_dir)));
    config = config::LoadConfig(options.config_file, overrides);
  }
  CheckResumedConfig(config, options.run_dir, options.allow_config_change);
  try {
    if (options.in_process) return RunInProcess(options, config);
    // DDS Security: every process's identity is in the keystore before anything starts
    config::SecurityConfig& security = config.transport.security;
    for (const std::string& name : {std::string("learner"), std::string("graph")}) config::CheckKeystore(security, name);
    for (int k = 0; k < config.actors.count; ++k) config::CheckKeystore(security, "actor-" + std::to_string(k));
    security.identity = config::CheckKeystore(security, "launcher");
    return RunProcesses(options, config);
  } catch (const dashboard::BindError& e) {
    // thrown before the run folder or any process exists (RunSession binds first)
    std::cerr << "srics run: " << e.what() << "\n";
    return kExitUsage;
  }
}

}  // namespace srics::launcher
