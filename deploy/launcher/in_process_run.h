#pragma once
// `srics run CONFIG --in-process`: the distributed run's own loops (GraphService, LearnerLoop,
// ActorLoop x actors.count) in one process, wired by the in-memory bus instead of DDS, stepped
// in a fixed order: on one thread, or (run.in_process_threads: 2) the learner on a second
// thread beside the actors, the bus holding each round's publications until both are done.
// Same run folder, display, CSV files and plots as the distributed run. Deterministic: the
// same config gives the same eval.csv, bit for bit, apart from the wall-clock column (unless
// run.max_wall_minutes cuts it short).

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/config/config.h"
#include "common/links/in_memory_bus.h"
#include "common/profile/phase_clock.h"
#include "deploy/launcher/launcher.h"
#include "graph_service/service.h"

namespace srics::launcher {

// The loops of one run wired in memory, stepped round by round. Used by RunInProcess and by
// tests that drive a whole run without processes.
struct InProcessOptions {
  // only the graph service and exploring actors; the run ends when the graph is published
  // (`srics learn-graph`)
  bool graph_only = false;
  std::function<void(const graph_service::Progress&)> on_graph_progress;  // may be empty
};

class InProcessRun {
 public:
  // `dir` holds graph.json and checkpoint.srics ("" = nothing saved; graph.ground_truth and
  // graph.file need a folder). `observer` sees every publication (may be null).
  InProcessRun(const config::Config& config, const std::string& dir, links::BusObserver* observer,
               InProcessOptions options = {});
  ~InProcessRun();

  // One round: the graph service, every actor, then the learner each take one step (with two
  // threads the actors and the learner at once, each seeing what the others published up to
  // the round before). Returns false once the learner has finished the budget and every actor
  // has ended. Throws std::runtime_error when no loop could make progress for many rounds (a
  // stall), and what a loop threw.
  bool Round();
  // Stops early (Ctrl-C, wall-clock limit): the learner publishes and checkpoints its final
  // state.
  void Stop();

  uint64_t rounds() const { return rounds_; }
  // CPU seconds per phase of both threads (profile::Enable()d; tests/bench.sh run-cost).
  profile::Totals PhaseTotals() const;
  // The graph service's state (null when the method uses no graph).
  const graph_service::GraphService* graph_service() const;

 private:
  struct Loops;
  class LearnerThread;
  bool StepActors();
  std::unique_ptr<Loops> loops_;
  std::unique_ptr<LearnerThread> learner_thread_;  // run.in_process_threads: 2
  InProcessOptions options_;
  uint64_t rounds_ = 0;
  uint64_t idle_rounds_ = 0;
};

int RunInProcess(const LaunchOptions& options, const config::Config& config);

// `srics learn-graph (--env FILE | --random-table N) --out DIR [--seed N] [--set ...]`: learns
// the interaction graph of an environment preset in process (exploring actors and the graph
// service) and leaves DIR/graph.json, graph.png, graph_weights.png. Returns an exit code.
struct LearnGraphOptions {
  std::string env_file;                // --env
  std::optional<uint64_t> table_seed;  // --random-table N: a random table instead of a file
  std::string out_dir;                 // --out
  std::optional<uint64_t> seed;        // --seed N
  std::vector<std::string> overrides;  // --set, in order, then run.seed=N of --seed N
  bool expected_only = false;          // --expected: print the graph by construction and exit
  bool evidence_only = false;          // --evidence: collect the data, print its tie evidence, stop
};
int LearnGraph(const LearnGraphOptions& options);

}  // namespace srics::launcher
