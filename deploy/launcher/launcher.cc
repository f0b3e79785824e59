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

#include "common/config/config.h"
#include "common/logging/logging.h"
#include "common/transport/transport.h"
#include "deploy/launcher/run_folder.h"
#include "deploy/monitor/display.h"
#include "deploy/monitor/monitor.h"

namespace srics::launcher {

namespace tr = srics::transport;
namespace mon = srics::monitor;
namespace fs = std::filesystem;

const char* const kRunUsage =
    "usage: srics run CONFIG [--actors N] [--set key.path=value ...] [--run-dir DIR] [--bin-dir DIR]\n"
    "                 [--display auto|live|plain|none] [--stop-timeout S] [--final-eval-grace S]\n"
    "  CONFIG          the run's config (e.g. deploy/configs/default.yaml)\n"
    "  --actors N      actor processes (default: actors.count of the config)\n"
    "  --set K=V       override a config value (recorded in the run folder's config.yaml)\n"
    "  --run-dir DIR   the run folder (default <run.output_dir>/<run.name>-<timestamp>); an existing\n"
    "                  one is continued: the learner resumes from its checkpoint\n"
    "  --bin-dir DIR   where srics-graph, srics-learner, srics-actor are (default: the build tree\n"
    "                  this program belongs to)\n"
    "  --display M     live (refreshing screen), plain (a line every 10 s), none, auto (live on a terminal)\n"
    "  --stop-timeout S      seconds between SIGINT and SIGKILL when stopping (default 15)\n"
    "  --final-eval-grace S  once the learner finished, wait this long for the actors' final\n"
    "                        evaluation and exit before stopping them (default 180)\n"
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

std::string Clock(double seconds) {
  char buffer[32];
  const auto s = static_cast<int64_t>(seconds);
  std::snprintf(buffer, sizeof buffer, "%02" PRId64 ":%02" PRId64 ":%02" PRId64, s / 3600, s / 60 % 60, s % 60);
  return buffer;
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
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw std::invalid_argument(arg + " needs a value");
      return args[++i];
    };
    if (arg == "--set") options.overrides.push_back(value());
    else if (arg == "--actors") options.actors = static_cast<int>(ParseNumber(arg, value(), 1));
    else if (arg == "--run-dir") options.run_dir = value();
    else if (arg == "--bin-dir") options.bin_dir = value();
    else if (arg == "--stop-timeout") options.stop_timeout_s = ParseNumber(arg, value(), 0);
    else if (arg == "--final-eval-grace") options.final_eval_grace_s = ParseNumber(arg, value(), 0);
    else if (arg == "--display") {
      const std::string& mode = value();
      if (mode == "auto") options.display = DisplayMode::kAuto;
      else if (mode == "live") options.display = DisplayMode::kLive;
      else if (mode == "plain") options.display = DisplayMode::kPlain;
      else if (mode == "none") options.display = DisplayMode::kNone;
      else throw std::invalid_argument("--display expects auto, live, plain or none, got '" + mode + "'");
    } else if (!arg.empty() && arg[0] == '-') {
      throw std::invalid_argument("unknown option " + arg);
    } else if (options.config_file.empty()) {
      options.config_file = arg;
    } else {
      throw std::invalid_argument("unexpected argument " + arg);
    }
  }
  if (options.config_file.empty()) throw std::invalid_argument("missing CONFIG");
  if (options.actors > 0) options.overrides.push_back("actors.count=" + std::to_string(options.actors));
  return options;
}

int Run(const LaunchOptions& options) {
  // config first: a bad one stops everything before a folder or a process exists
  const config::Config config = config::LoadConfig(options.config_file, options.overrides);
  const std::string graph_bin = FindProgram("srics-graph", "graph_service", options.bin_dir);
  const std::string learner_bin = FindProgram("srics-learner", "learner", options.bin_dir);
  const std::string actor_bin = FindProgram("srics-actor", "actor", options.bin_dir);

  const std::string dir = PrepareRunFolder(config, options.run_dir);
  const std::string config_path = dir + "/config.yaml";
  DisplayMode display = options.display;
  if (display == DisplayMode::kAuto) display = isatty(STDOUT_FILENO) ? DisplayMode::kLive : DisplayMode::kPlain;
  auto logger = logging::SetUpLogger("launcher", {.level = config.run.log_level, .file = dir + "/logs/launcher.log"});
  if (display == DisplayMode::kLive) logger->sinks().front()->set_level(spdlog::level::off);
  logger->flush_on(spdlog::level::info);
  std::cout << "srics run: run folder " << dir << "\n" << std::flush;
  spdlog::info("run folder {}, config {}, {} actors", dir, options.config_file, config.actors.count);

  const auto start = SteadyClock::now();
  std::deque<std::string> events;
  auto note = [&](const std::string& text) {  // on the display only
    events.push_back("[" + Clock(std::chrono::duration<double>(SteadyClock::now() - start).count()) + "] " + text);
    if (events.size() > 8) events.pop_front();
  };
  auto event = [&](const std::string& text) {  // logged and on the display
    spdlog::info("{}", text);
    events.push_back("[" + Clock(std::chrono::duration<double>(SteadyClock::now() - start).count()) + "] " + text);
    if (events.size() > 8) events.pop_front();
  };

  // what the processes publish, to the display and to eval.csv, learner.csv, nodes.csv
  tr::Participant participant(config.transport);
  mon::Monitor monitor(participant, {.all_runs = false, .weights = true, .csv_dir = dir, .csv_node_statuses = true});

  SupervisorOptions supervisor_options;
  supervisor_options.backoff = options.backoff;
  supervisor_options.stop_timeout = std::chrono::milliseconds(static_cast<int64_t>(options.stop_timeout_s * 1000));
  supervisor_options.on_event = event;
  Supervisor supervisor(supervisor_options);
  const std::vector<std::string> common = {config_path, "--run-dir", dir};
  auto argv = [&](const std::string& bin, std::vector<std::string> extra) {
    std::vector<std::string> v = {bin};
    v.insert(v.end(), common.begin(), common.end());
    v.insert(v.end(), extra.begin(), extra.end());
    return v;
  };
  const size_t graph = supervisor.Add({.name = "graph", .argv = argv(graph_bin, {}),
                                       .output_file = dir + "/logs/graph.out",
                                       .max_restarts = options.max_restarts_service});
  const size_t learner = supervisor.Add({.name = "learner", .argv = argv(learner_bin, {}),
                                         .output_file = dir + "/logs/learner.out",
                                         .max_restarts = options.max_restarts_service});
  std::vector<size_t> actors;
  for (int k = 0; k < config.actors.count; ++k)
    actors.push_back(supervisor.Add({.name = "actor-" + std::to_string(k),
                                     .argv = argv(actor_bin, {"--id", std::to_string(k)}),
                                     .output_file = dir + "/logs/actor-" + std::to_string(k) + ".out"}));
  try {
    supervisor.StartAll();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    std::cerr << "srics run: " << e.what() << "\n";
    return kExitFailed;
  }

  mon::RenderOptions render;
  render.title = "srics run  " + dir + "  (Ctrl-C stops)";
  render.run_id = config.transport.run_id;
  render.total_env_steps = config.run.total_env_steps;
  render.max_wall_minutes = config.run.max_wall_minutes;

  int exit_code = kExitDone;
  std::string reason;
  std::optional<SteadyClock::time_point> learner_done;   // the learner exited with 0
  std::optional<SteadyClock::time_point> actors_down_at;  // no actor running or restarting
  auto next_draw = start;
  auto next_line = start + std::chrono::seconds(10);
  while (reason.empty()) {
    if (participant.shutdown_requested()) {
      reason = "interrupted";
      exit_code = kExitInterrupted;
      break;
    }
    monitor.Poll(std::chrono::milliseconds(200));
    for (const std::string& text : monitor.TakeNodeEvents()) note(text);  // the monitor logged it
    for (size_t i : supervisor.Tick()) {
      const ChildStatus& s = supervisor.status(i);
      if (i == learner && s.phase == ChildPhase::kFinished) {
        learner_done = SteadyClock::now();
        event("the learner finished its budget; waiting for the actors' final evaluation");
      } else if ((i == learner || i == graph) && s.phase == ChildPhase::kFailed) {
        reason = s.name + " failed for good (" + (s.last_exit ? s.last_exit->Describe() : "?") + ")";
        exit_code = kExitFailed;
      }
    }
    if (!reason.empty()) break;
    bool actors_down = true, actor_failed = false;
    for (size_t i : actors) {
      const ChildPhase phase = supervisor.status(i).phase;
      actors_down &= phase != ChildPhase::kRunning && phase != ChildPhase::kWaitingToRestart;
      actor_failed |= phase == ChildPhase::kFailed;
    }
    const auto now = SteadyClock::now();
    const double elapsed = std::chrono::duration<double>(now - start).count();
    const auto grace = std::chrono::duration<double>(options.final_eval_grace_s);
    if (actors_down && !actors_down_at) actors_down_at = now;
    if (learner_done && actors_down) {
      reason = actor_failed ? "the budget is done, but actors failed" : "the budget is done";
      exit_code = actor_failed ? kExitFailed : kExitDone;
    } else if (learner_done && now - *learner_done >= grace) {
      reason = "the budget is done (actors did not finish within the grace period)";
    } else if (!learner_done && !actors.empty() && actors_down && now - *actors_down_at >= grace) {
      reason = "every actor ended but the learner did not finish";
      exit_code = kExitFailed;
    } else if (config.run.max_wall_minutes > 0 && elapsed >= config.run.max_wall_minutes * 60.0) {
      char text[96];
      std::snprintf(text, sizeof text, "wall-clock limit of %g minutes reached", config.run.max_wall_minutes);
      reason = text;
    }

    if (display == DisplayMode::kLive && now >= next_draw) {
      next_draw = now + std::chrono::seconds(1);
      render.elapsed_s = elapsed;
      render.processes = ProcessRows(supervisor, now);
      render.events.assign(events.begin(), events.end());
      std::cout << "\033[H\033[2J" << mon::Render(monitor.state(), mon::Clock::now(), render) << std::flush;
    } else if (display == DisplayMode::kPlain && now >= next_line) {
      next_line = now + std::chrono::seconds(10);
      std::cout << "[" << Clock(elapsed) << "] "
                << mon::RenderOneLine(monitor.state(), mon::Clock::now(), config.transport.run_id,
                                      config.run.total_env_steps)
                << "  restarts " << supervisor.total_restarts() << std::endl;
    }
  }

  event("stopping: " + reason);
  if (display == DisplayMode::kLive) std::cout << "\nstopping (" << reason << ") ...\n" << std::flush;
  const bool clean = supervisor.StopAll();
  monitor.Poll(std::chrono::milliseconds(0));  // what the roles said last
  const double elapsed = std::chrono::duration<double>(SteadyClock::now() - start).count();

  std::string plot_error;
  const bool plotted = PlotEvalCurves(dir, config::MethodName(config.run.method) + std::string(" - ") +
                                               fs::path(dir).filename().string(), &plot_error);
  if (!plotted) event("no learning-curve plot: " + plot_error);

  render.title = "srics run  " + dir + "  finished: " + reason;
  render.elapsed_s = elapsed;
  render.processes = ProcessRows(supervisor, SteadyClock::now());
  render.events.assign(events.begin(), events.end());
  const std::string summary = mon::Render(monitor.state(), mon::Clock::now(), render);
  std::ofstream(dir + "/summary.txt") << summary;

  std::string files;
  for (const char* name : {"config.yaml", "eval.csv", "learner.csv", "nodes.csv", "curve.png", "subgoal_success.png",
                           "graph.json", "graph.png", "checkpoint.srics", "summary.txt", "logs"})
    if (fs::exists(fs::path(dir) / name)) files += std::string(files.empty() ? "" : ", ") + name;
  std::cout << (display == DisplayMode::kLive ? "\033[H\033[2J" : "\n") << summary << "\n"
            << "run " << (exit_code == kExitDone ? "finished" : exit_code == kExitInterrupted ? "interrupted" : "FAILED")
            << ": " << reason << (clean ? "" : " (some processes had to be killed)") << "; restarts "
            << supervisor.total_restarts() << "\nrun folder " << dir << ": " << files << "\n"
            << std::flush;
  spdlog::info("done: {} (exit code {}), files: {}", reason, exit_code, files);
  return exit_code;
}

}  // namespace srics::launcher
