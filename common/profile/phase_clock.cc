#include "common/profile/phase_clock.h"

#include <time.h>

#include <atomic>
#include <vector>

namespace srics::profile {
namespace {

std::atomic<bool> enabled{false};

double CpuSeconds(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct ThreadClock {
  Totals totals{};
  std::vector<Phase> open;  // innermost last
  double since = 0;         // when the innermost phase was last charged
  // charges the time since the last charge to the innermost open phase
  void Charge(double now) {
    if (!open.empty()) totals[static_cast<size_t>(open.back())] += now - since;
    since = now;
  }
};

thread_local ThreadClock clock_of_thread;

}  // namespace

std::string_view PhaseName(Phase phase) {
  switch (phase) {
    case Phase::kEnvStep: return "env_step";
    case Phase::kActing: return "acting";
    case Phase::kEvaluation: return "evaluation";
    case Phase::kReplaySampling: return "replay_sampling";
    case Phase::kSacUpdate: return "sac_update";
    case Phase::kLearner: return "learner";
    case Phase::kGraph: return "graph";
    case Phase::kCount: break;
  }
  return "?";
}

double ThreadCpuSeconds() { return CpuSeconds(CLOCK_THREAD_CPUTIME_ID); }
double ProcessCpuSeconds() { return CpuSeconds(CLOCK_PROCESS_CPUTIME_ID); }

void Enable() { enabled.store(true, std::memory_order_relaxed); }
bool Enabled() { return enabled.load(std::memory_order_relaxed); }

Totals Snapshot() {
  ThreadClock& c = clock_of_thread;
  c.Charge(ThreadCpuSeconds());
  return c.totals;
}

PhaseScope::PhaseScope(Phase phase) {
  if (!Enabled()) return;
  ThreadClock& c = clock_of_thread;
  if (!c.open.empty() && c.open.back() == Phase::kEvaluation) return;  // evaluations count whole
  c.Charge(ThreadCpuSeconds());
  c.open.push_back(phase);
  open_ = true;
}

PhaseScope::~PhaseScope() {
  if (!open_) return;
  ThreadClock& c = clock_of_thread;
  c.Charge(ThreadCpuSeconds());
  c.open.pop_back();
}

}  // namespace srics::profile
