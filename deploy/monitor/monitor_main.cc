// srics-monitor: attaches to a running system (this host or another) and shows nodes, learner
// stats, evaluations and the graph live; optionally appends everything to CSV files.
//
//   srics-monitor CONFIG [--set key.path=value ...] [--csv DIR] [--once] [--all-runs]
//                 [--no-weights] [--for SECONDS] [--wait SECONDS] [--refresh SECONDS]
//
// Exit codes: 0 ok, 2 bad arguments or config, 1 DDS failure, 3 with --once: nothing received.

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <iostream>
#include <string>
#include <vector>

#include <spdlog/sinks/sink.h>

#include "common/config/command_line.h"
#include "common/config/config.h"
#include "common/logging/logging.h"
#include "common/transport/transport.h"
#include "deploy/monitor/display.h"
#include "deploy/monitor/monitor.h"

namespace {

namespace tr = srics::transport;
namespace mon = srics::monitor;

constexpr const char* kUsage =
    "usage: srics-monitor CONFIG [--set key.path=value ...] [--csv DIR] [--once] [--all-runs]\n"
    "                     [--no-weights] [--for SECONDS] [--wait SECONDS] [--refresh SECONDS]\n"
    "  CONFIG        the run's config (domain id, run id, Cyclone profile come from it)\n"
    "  --set K=V     override a config value, as for the other srics programs\n"
    "  --csv DIR     append eval.csv, learner.csv, nodes.csv in DIR as samples arrive\n"
    "  --once        listen for --wait seconds (default 3), print one display and exit\n"
    "                (exit code 3 when nothing at all was received)\n"
    "  --all-runs    show every run id on the domain, not only the config's\n"
    "  --no-weights  do not subscribe to PolicyWeights (saves 5 MB per publication per host)\n"
    "  --for S       stop after S seconds (default: until Ctrl-C)\n"
    "  --refresh S   display refresh period (default 1)\n";

struct Args {
  std::string config;
  std::vector<std::string> overrides;
  std::string csv_dir;
  bool once = false;
  bool all_runs = false;
  bool weights = true;
  double for_s = 0;
  double wait_s = 3;
  double refresh_s = 1;
};

double ParseSeconds(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(value >= 0))
    throw std::invalid_argument(flag + " expects a number of seconds >= 0, got '" + text + "'");
  return value;
}

Args ParseArgs(int argc, char** argv) {
  Args args;
  for (srics::config::ArgumentReader r(argc, argv); r.Next();) {
    const std::string& arg = r.arg();
    auto value = [&r] { return r.Value(); };
    if (arg == "--set") args.overrides.push_back(value());
    else if (arg == "--csv") args.csv_dir = value();
    else if (arg == "--once") args.once = true;
    else if (arg == "--all-runs") args.all_runs = true;
    else if (arg == "--no-weights") args.weights = false;
    else if (arg == "--for") args.for_s = ParseSeconds(arg, value());
    else if (arg == "--wait") args.wait_s = ParseSeconds(arg, value());
    else if (arg == "--refresh") args.refresh_s = std::max(0.1, ParseSeconds(arg, value()));
    else if (arg == "-h" || arg == "--help") { std::cout << kUsage; std::exit(0); }
    else if (!arg.empty() && arg[0] == '-') throw std::invalid_argument("unknown option " + arg);
    else if (args.config.empty()) args.config = arg;
    else throw std::invalid_argument("unexpected argument " + arg);
  }
  if (args.config.empty()) throw std::invalid_argument("missing CONFIG");
  return args;
}

}  // namespace

int main(int argc, char** argv) {
  tr::Shutdown::InstallSignalHandlers();
  Args args;
  srics::config::Config config;
  try {
    args = ParseArgs(argc, argv);
    config = srics::config::LoadConfig(args.config, args.overrides);
    // DDS Security: the keystore's "monitor" identity (read-only) unless the config names another
    config.transport.security.identity = srics::config::CheckKeystore(config.transport.security, "monitor");
  } catch (const std::exception& e) {
    std::cerr << "srics-monitor: " << e.what() << "\n" << kUsage;
    return 2;
  }
  // the config's run id is chosen per launch (a config file, not a run folder's config.yaml):
  // show every run on the domain
  if (config.transport.run_id == srics::config::kAutoRunId) args.all_runs = true;
  const bool live = !args.once && isatty(STDOUT_FILENO);
  auto logger = srics::logging::SetUpLogger("monitor", {.level = config.run.log_level, .file = ""});
  // a refreshing screen and log lines on the same terminal do not mix: events go on screen
  if (live) logger->sinks().front()->set_level(spdlog::level::off);

  try {
    tr::Participant participant(config.transport);
    mon::Monitor monitor(participant, {.all_runs = args.all_runs, .weights = args.weights, .csv_dir = args.csv_dir, .csv_node_statuses = true});
    mon::RenderOptions render;
    render.run_id = args.all_runs ? "" : config.transport.run_id;
    render.total_env_steps = config.run.total_env_steps;
    render.title = "srics-monitor  domain " + std::to_string(config.transport.domain_id) +
                   (args.all_runs ? "  all runs" : "  run " + config.transport.run_id);
    std::deque<std::string> events;

    const auto start = mon::Clock::now();
    const auto refresh = std::chrono::duration_cast<mon::Clock::duration>(std::chrono::duration<double>(args.refresh_s));
    auto next_draw = start;
    size_t received = 0;
    while (!participant.shutdown_requested()) {
      const auto now = mon::Clock::now();
      const double elapsed = std::chrono::duration<double>(now - start).count();
      if (args.once && elapsed >= args.wait_s) break;
      if (args.for_s > 0 && elapsed >= args.for_s) break;
      received += monitor.Poll(std::chrono::milliseconds(100));
      for (std::string& event : monitor.TakeNodeEvents()) {
        events.push_back(std::move(event));
        if (events.size() > 8) events.pop_front();
      }
      if (args.once || mon::Clock::now() < next_draw) continue;
      next_draw = mon::Clock::now() + (live ? refresh : refresh * 10);
      render.events.assign(events.begin(), events.end());
      if (live) {
        std::cout << "\033[H\033[2J" << mon::Render(monitor.state(), mon::Clock::now(), render) << std::flush;
      } else {
        std::cout << mon::RenderOneLine(monitor.state(), mon::Clock::now(), config.transport.run_id,
                                        config.run.total_env_steps)
                  << std::endl;
      }
    }
    render.events.assign(events.begin(), events.end());
    if (args.once || !live) std::cout << mon::Render(monitor.state(), mon::Clock::now(), render) << std::flush;
    if (args.once && received == 0) return 3;
    return 0;
  } catch (const std::exception& e) {
    spdlog::error("srics-monitor: {}", e.what());
    std::cerr << "srics-monitor: " << e.what() << "\n";
    return 1;
  }
}
