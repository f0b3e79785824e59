// srics-monitor: attaches to a running system (this host or another) and shows nodes, learner
// stats, evaluations and the graph live; optionally appends everything to CSV files.
//
//   srics-monitor CONFIG [--set key.path=value ...] [--csv DIR] [--once] [--all-runs]
//                 [--no-weights] [--for SECONDS] [--wait SECONDS] [--refresh SECONDS]
//                 [--http PORT [--http-bind ADDR]] [--json]
//   srics-monitor --run-dir DIR [...]     a run folder's files instead of DDS (live or finished)
//
// Exit codes: 0 ok, 2 bad arguments or config (or a port that cannot be served), 1 DDS
// failure, 3 with --once: nothing received.

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/sinks/sink.h>

#include "common/cli/cli.h"
#include "common/config/config.h"
#include "common/logging/logging.h"
#include "common/transport/transport.h"
#include "deploy/dashboard/dashboard.h"
#include "deploy/dashboard/run_folder_watch.h"
#include "deploy/monitor/display.h"
#include "deploy/monitor/monitor.h"

namespace {

namespace tr = srics::transport;
namespace mon = srics::monitor;

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
  std::string run_dir;                  // --run-dir
  int http_port = -1;                   // --http (-1: no dashboard)
  std::string http_bind = "127.0.0.1";  // --http-bind
  bool json = false;                    // --json
};

// Parses the command line into *args: nothing when the program goes on, else its exit code
// (0 after --help or --version, 2 for a bad argument).
std::optional<int> ParseArgs(int argc, char** argv, Args* args) {
  CLI::App app{
      "attaches to a running system (this host or another) and shows nodes, learner stats, evaluations and "
      "the graph live; optionally appends everything to CSV files. Exit codes: 0 ok, 1 DDS failure, 2 bad "
      "arguments or config, 3 with --once: nothing received",
      "srics-monitor"};
  srics::cli::Configure(app);
  app.add_option("CONFIG", args->config,
                 "the run's config (domain id, run id, Cyclone profile come from it); optional with --run-dir")
      ->transform(srics::cli::InstalledConfig());
  srics::cli::AddSetOption(app, &args->overrides, "override a config value, as for the other srics programs");
  app.add_option("--csv", args->csv_dir, "append eval.csv, learner.csv, nodes.csv in DIR as samples arrive")
      ->type_name("DIR");
  app.add_flag("--once", args->once,
               "listen for --wait seconds, print one display and exit (exit code 3 when nothing at all was received)");
  app.add_flag("--all-runs", args->all_runs, "show every run id on the domain, not only the config's");
  app.add_flag_callback(
      "--no-weights", [args] { args->weights = false; },
      "do not subscribe to PolicyWeights (saves 5 MB per publication per host)");
  app.add_option("--for", args->for_s, "stop after S seconds (0: until Ctrl-C)")->check(srics::cli::Number(0));
  app.add_option("--wait", args->wait_s, "with --once: seconds to listen")->check(srics::cli::Number(0));
  app.add_option("--refresh", args->refresh_s, "display refresh period in seconds (at least 0.1)")
      ->check(srics::cli::Number(0));
  app.add_option("--run-dir", args->run_dir,
                 "a run folder's files (eval.csv, learner.csv, nodes.csv, graph.json; a finished run or one going on) "
                 "instead of DDS; with CONFIG: where recorded episodes are")
      ->type_name("DIR");
  CLI::Option* http = app.add_option("--http", args->http_port,
                                     "serve the web dashboard on PORT (0: any free port; the URL is printed)")
                          ->check(srics::cli::Integer(0, 65535))
                          ->type_name("PORT")
                          ->default_str("");
  app.add_option("--http-bind", args->http_bind,
                 "the dashboard's address (127.0.0.1: this host only; 0.0.0.0 = every interface)")
      ->needs(http)
      ->type_name("ADDR");
  app.add_flag("--json", args->json,
               "print the dashboard's JSON document, one line per refresh, instead of the display");
  if (const auto code = srics::cli::Parse(app, argc, argv)) return code;
  if (args->config.empty() && args->run_dir.empty())
    return srics::cli::UsageError("srics-monitor", "missing CONFIG (or --run-dir DIR)");
  args->refresh_s = std::max(0.1, args->refresh_s);
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  tr::Shutdown::InstallSignalHandlers();
  Args args;
  if (const auto code = ParseArgs(argc, argv, &args)) return *code;
  srics::config::Config config;
  try {
    if (args.config.empty())  // --run-dir alone: the folder's files, not DDS
      return srics::dashboard::WatchRunFolder({.run_dir = args.run_dir,
                                               .http_port = args.http_port,
                                               .http_bind = args.http_bind,
                                               .json = args.json,
                                               .once = args.once,
                                               .for_s = args.for_s,
                                               .refresh_s = args.refresh_s});
    config = srics::config::LoadConfig(args.config, args.overrides);
    // DDS Security: the keystore's "monitor" identity (read-only) unless the config names another
    config.transport.security.identity = srics::config::CheckKeystore(config.transport.security, "monitor");
  } catch (const std::exception& e) {
    std::cerr << "srics-monitor: " << e.what() << "\n";
    return srics::kExitUsage;
  }
  // the config's run id is chosen per launch (a config file, not a run folder's config.yaml):
  // show every run on the domain
  if (config.transport.run_id == srics::config::kAutoRunId) args.all_runs = true;
  const bool live = !args.once && !args.json && isatty(STDOUT_FILENO);
  auto logger = srics::logging::SetUpLogger("monitor", {.level = config.run.log_level, .file = ""});
  // a refreshing screen and log lines on the same terminal do not mix: events go on screen
  if (live || args.json) logger->sinks().front()->set_level(spdlog::level::off);
  std::unique_ptr<srics::dashboard::Dashboard> dashboard;
  try {
    if (args.http_port >= 0)
      dashboard = std::make_unique<srics::dashboard::Dashboard>(srics::dashboard::DashboardOptions{
          .bind = args.http_bind, .port = args.http_port, .source = "dds", .run_dir = args.run_dir});
  } catch (const srics::dashboard::BindError& e) {
    std::cerr << "srics-monitor: " << e.what() << "\n";
    return srics::kExitUsage;
  }
  if (dashboard) std::cerr << "srics-monitor: dashboard on " << dashboard->url() << std::endl;
  auto json_line = [&](const srics::monitor::MonitorState& state, const srics::monitor::RenderOptions& render) {
    return srics::dashboard::DocumentFor(state, srics::monitor::Clock::now(), render, "dds", args.run_dir);
  };

  try {
    tr::Participant participant(config.transport);
    mon::Monitor monitor(
        participant,
        {.all_runs = args.all_runs, .weights = args.weights, .csv_dir = args.csv_dir, .csv_node_statuses = true});
    mon::RenderOptions render;
    render.run_id = args.all_runs ? "" : config.transport.run_id;
    render.total_env_steps = config.run.total_env_steps;
    render.title = "srics-monitor  domain " + std::to_string(config.transport.domain_id) +
                   (args.all_runs ? "  all runs" : "  run " + config.transport.run_id);
    std::deque<std::string> events;

    const auto start = mon::Clock::now();
    const auto refresh =
        std::chrono::duration_cast<mon::Clock::duration>(std::chrono::duration<double>(args.refresh_s));
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
      render.events.assign(events.begin(), events.end());
      if (dashboard) dashboard->Update(monitor.state(), mon::Clock::now(), render);
      if (args.once || mon::Clock::now() < next_draw) continue;
      next_draw = mon::Clock::now() + (live || args.json ? refresh : refresh * 10);
      // lines clipped to the terminal's width (not in files and pipes); JSON lines never
      const size_t width = mon::OutputWidth(STDOUT_FILENO);
      if (args.json) {
        std::cout << json_line(monitor.state(), render) << std::endl;
      } else if (live) {
        mon::RenderOptions shown = render;
        if (dashboard) shown.title += "  dashboard " + dashboard->url();  // the screen hides the printed URL
        std::cout << "\033[H\033[2J" << mon::ClipLines(mon::Render(monitor.state(), mon::Clock::now(), shown), width)
                  << std::flush;
      } else {
        std::cout << mon::ClipLines(mon::RenderOneLine(monitor.state(), mon::Clock::now(), config.transport.run_id,
                                                       config.run.total_env_steps),
                                    width)
                  << std::endl;
      }
    }
    render.events.assign(events.begin(), events.end());
    if (args.json && args.once)
      std::cout << json_line(monitor.state(), render) << std::endl;
    else if (!args.json && (args.once || !live))
      std::cout << mon::ClipLines(mon::Render(monitor.state(), mon::Clock::now(), render),
                                  mon::OutputWidth(STDOUT_FILENO))
                << std::flush;
    if (args.once && received == 0) return srics::kExitNothingReceived;
    return 0;
  } catch (const std::exception& e) {
    spdlog::error("srics-monitor: {}", e.what());
    std::cerr << "srics-monitor: " << e.what() << "\n";
    return 1;
  }
}
