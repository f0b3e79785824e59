#pragma once
// `srics run`: one training run on this machine. Starts srics-graph, srics-learner and N
// srics-actor processes over loopback DDS (or whatever profile the config names), shows one
// live progress display, restarts crashed processes, stops everything on Ctrl-C or when the
// run is done, and leaves the run folder complete.
//
// When the run is done: the learner owns the budget (run.total_env_steps). When it has
// trained on all of it, it publishes its final weights and stats (budget done) and exits with
// code 0; the actors see the budget done in LearnerStats, the evaluating ones run a last
// evaluation, and they exit with 0. The launcher then stops the graph service (SIGINT) and
// finishes the run folder. If the actors are not done within final_eval_grace_s after the
// learner, they are stopped. run.max_wall_minutes (if > 0) stops everything when it passes
// (the learner checkpoints on SIGINT). Crashed processes (a signal or a non-zero exit) are
// restarted with backoff; the learner and the graph service at most max_restarts_service
// times (the learner resumes from its checkpoint, the graph service from graph.json).
//
// Several hosts: `--roles learner,graph` on one host and `--roles actor --ids 2-5` on another
// give each host the same supervisor, restarts and display for its share of the roles (the
// display shows every node of the run, from DDS). A host without the learner learns that the
// budget is done from the learner's stats; its actors then end by themselves (final
// evaluation included) and a host without actors stops its graph service.

#include <chrono>
#include <string>
#include <vector>

#include "common/cli/exit_codes.h"
#include "common/config/config.h"
#include "deploy/launcher/supervisor.h"

namespace srics::launcher {

enum class DisplayMode {
  kAuto,   // live when stdout is a terminal, else plain
  kLive,   // the refreshing full-screen display
  kPlain,  // a progress line every 10 s (for logs and pipes)
  kNone,   // nothing but the final summary
};

// What `srics run` was asked (its command line: command_line.cc).
struct LaunchOptions {
  std::string config_file;
  std::vector<std::string> overrides;  // --set key.path=value
  int actors = -1;                     // --actors N (-1: actors.count of the config)
  std::string run_dir;                 // --run-dir ("" = <output_dir>/<name>-<timestamp>)
  std::string bin_dir;                 // --bin-dir ("" = next to this executable / build tree)
  DisplayMode display = DisplayMode::kAuto;
  bool in_process = false;              // --in-process: one process, in-memory links
  double stop_timeout_s = 15;           // SIGINT -> SIGKILL
  double final_eval_grace_s = 180;      // after the learner finished: wait for the actors
  BackoffPolicy backoff;                // restarts of crashed processes
  int max_restarts_service = 5;         // learner and graph service (actors: no limit)
  std::string label;                    // --label: shown in the display's title ("sweep run 2/6")
  bool allow_config_change = false;     // --allow-config-change: a continued run may take another config
  int http_port = -1;                   // --http PORT: serve the web dashboard (-1 = none, 0 = any free port)
  std::string http_bind = "127.0.0.1";  // --http-bind ADDR
  // --roles graph,learner,actor: this host's share of a run on several hosts (empty: every
  // role, the whole run here); --ids 2-5: its actors (empty: 0 .. actors.count - 1)
  std::vector<std::string> roles;
  std::vector<int> actor_ids;
};

// The roles a launch runs on this host: graph, learner and the actor ids.
struct RoleShare {
  bool graph = true;
  bool learner = true;
  std::vector<int> actor_ids;
  bool whole_run = true;  // every role and actor of the config: not a share
};
// The share that options.roles and options.actor_ids ask for, with the config's actors.count.
RoleShare ShareOf(const LaunchOptions& options, const config::Config& config);

// `srics run` exits with kExitDone, kExitFailed (a role failed for good, or no child could
// start), kExitUsage (bad arguments or config, or a run of this run id is live: run_guard.h) or
// kExitInterrupted (common/cli/exit_codes.h).

// Runs to the end; returns one of the exit codes above. Config errors throw ConfigError
// before anything is started; a share of a run (--roles) without an explicit
// transport.run_id throws std::invalid_argument (every host must use the same id).
int Run(const LaunchOptions& options);

}  // namespace srics::launcher
