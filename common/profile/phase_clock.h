#pragma once
// Where a run's CPU time goes, by phase (tests/bench.sh run-cost): the thread CPU time spent in
// each phase, charged to the innermost open phase (a phase opened inside another pauses the
// outer one), except inside an evaluation, which keeps its env steps and actions: evaluation
// episodes are counted whole. Off until Enable(): a closed scope then costs one branch.
//
//   profile::Enable();
//   { profile::PhaseScope scope(profile::Phase::kEnvStep); env.Step(...); }
//   profile::Totals totals = profile::Snapshot();   // seconds per phase, this thread's
//
// Per thread: the in-process run steps every loop on one thread; a phase opened on another
// thread is charged to that thread's totals, which Snapshot() does not see.

#include <array>
#include <cstddef>
#include <string_view>

namespace srics::profile {

enum class Phase : int {
  kEnvStep,         // MuJoCo stepping of training episodes
  kActing,          // the actors' loops besides env steps: policy actions, observations, episodes
  kEvaluation,      // evaluation episodes, whole (their env steps and actions included)
  kReplaySampling,  // sampling the replay and relabeling goals, rewards recomputed
  kSacUpdate,       // the SAC update of one batch (forward, backward, optimizer, targets)
  kLearner,         // the learner's loop besides sampling and updates: ingest, stats, checkpoints
  kGraph,           // the graph service: explore episodes, GNN training, read-out
  kCount
};
inline constexpr size_t kPhases = static_cast<size_t>(Phase::kCount);
std::string_view PhaseName(Phase phase);  // "env_step", "acting", ...

using Totals = std::array<double, kPhases>;  // CPU seconds per phase

void Enable();
bool Enabled();
// CPU seconds used so far by this thread / by the whole process.
double ThreadCpuSeconds();
double ProcessCpuSeconds();
// This thread's CPU seconds per phase so far (the open phases charged up to now).
Totals Snapshot();

class PhaseScope {
 public:
  explicit PhaseScope(Phase phase);
  ~PhaseScope();
  PhaseScope(const PhaseScope&) = delete;
  PhaseScope& operator=(const PhaseScope&) = delete;

 private:
  bool open_ = false;
};

}  // namespace srics::profile
