#pragma once
// `srics sweep CONFIG --methods M1,M2 --seeds 1,2,3 [--set K=V ...] [--out DIR] [--in-process]
// [--parallel N]`: a grid of runs (every method x every seed) in one sweep folder, one run
// folder per cell (DIR/<method>-seed<N>), each run by `srics run` as a child process, one
// after another (or N at a time).
//
// Resumable: running the same command again skips the runs whose outcome.yaml says
// "finished" and continues every other run folder where it was (the learner from its
// checkpoint with its replay, the graph service from its saved graph, actors from their next
// episode ids). DIR/sweep.yaml records the grid; another grid into the same folder, or a run
// whose effective configuration changed since it started, is refused before anything runs.
//
// Ctrl-C (SIGINT/SIGTERM): one SIGINT to every running run (it checkpoints and records
// "interrupted"), then the sweep exits with 130. A killed sweep (or machine) leaves its runs
// with their last periodic checkpoints; the next start continues from them.

#include <cstdint>
#include <string>
#include <vector>

#include "deploy/launcher/launcher.h"

namespace srics::launcher {

struct SweepOptions {
  std::string config_file;
  std::vector<std::string> methods;    // --methods, as run.method names
  std::vector<uint64_t> seeds;         // --seeds
  std::vector<std::string> overrides;  // --set, for every run
  std::string out_dir;                 // --out ("" = <run.output_dir>/<run.name>-sweep)
  bool in_process = false;             // --in-process: each run is `srics run --in-process`
  int parallel = 1;                    // --parallel: runs at a time
  // each run's own display; with --parallel above 1 runs print plain lines into
  // <sweep>/logs/<run>.out and the sweep shows each one's latest line
  DisplayMode display = DisplayMode::kAuto;
  std::string program;          // --program: the srics to run ("" = this executable)
  double stop_timeout_s = 180;  // after the SIGINT, the time a run has to checkpoint and exit
};

// One cell of the grid.
struct SweepRun {
  std::string method;
  uint64_t seed = 0;
  std::string name;                    // "<method>-seed<seed>"
  std::string dir;                     // <sweep folder>/<name>
  std::vector<std::string> overrides;  // the sweep's --set, then run.method, run.seed, run.name, transport.run_id
  std::string effective_yaml;          // the configuration the run gets (config.yaml of its folder)
  std::string resolved_yaml;           // every setting, defaults filled in (resolved-config.yaml)
};

struct SweepPlan {
  std::string dir;       // the sweep folder (absolute)
  std::string config;    // the config file (absolute)
  std::string manifest;  // sweep.yaml's text for this grid
  std::vector<SweepRun> runs;
};

// The sweep folder and its runs. Every run's config is loaded here, so a bad method name or
// --set throws config::ConfigError (naming the key, e.g. run.method) before anything starts.
// Throws std::invalid_argument for a --set of what the sweep sets itself (run.method,
// run.seed, run.name).
SweepPlan PlanSweep(const SweepOptions& options);

// Checks the plan against the folder: writes sweep.yaml into a new (or empty) folder; when
// the folder has one, it must describe the same grid; every existing run folder's
// config.yaml must be the configuration the run would get now. Throws std::invalid_argument
// with the difference otherwise.
void CheckSweepFolder(const SweepPlan& plan);

// Runs the sweep; returns 0 when every run has finished, 1 when some run failed (the others
// were run; the same command retries it), 2 for bad arguments, config or a different grid in
// the folder (nothing is started), 130 when interrupted.
int Sweep(const SweepOptions& options);

}  // namespace srics::launcher
