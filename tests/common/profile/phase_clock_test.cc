// The run-cost bench's phase clock: CPU time goes to the innermost open phase, evaluations keep
// what runs inside them, nothing is counted before Enable().
#include "common/profile/phase_clock.h"

#include <gtest/gtest.h>

namespace srics::profile {
namespace {

// Burns about `seconds` of this thread's CPU time.
void Burn(double seconds) {
  const double end = ThreadCpuSeconds() + seconds;
  volatile double sink = 0;
  while (ThreadCpuSeconds() < end) sink = sink + 1.0;
}

double Of(const Totals& t, Phase p) { return t[static_cast<size_t>(p)]; }

TEST(PhaseClockTest, ChargesTheInnermostPhaseAndEvaluationsWhole) {
  {
    PhaseScope off(Phase::kEnvStep);
    Burn(0.01);
  }
  EXPECT_EQ(Of(Snapshot(), Phase::kEnvStep), 0.0) << "counted before Enable()";
  Enable();
  const Totals before = Snapshot();
  {
    PhaseScope acting(Phase::kActing);
    Burn(0.05);
    {
      PhaseScope env(Phase::kEnvStep);
      Burn(0.10);
    }  // paused acting
    {
      PhaseScope eval(Phase::kEvaluation);
      Burn(0.03);
      PhaseScope env_inside(Phase::kEnvStep);  // stays the evaluation's
      Burn(0.04);
    }
  }
  Burn(0.02);  // no phase: neither
  const Totals after = Snapshot();
  EXPECT_NEAR(Of(after, Phase::kActing) - Of(before, Phase::kActing), 0.05, 0.01);
  EXPECT_NEAR(Of(after, Phase::kEnvStep) - Of(before, Phase::kEnvStep), 0.10, 0.01);
  EXPECT_NEAR(Of(after, Phase::kEvaluation) - Of(before, Phase::kEvaluation), 0.07, 0.01);
  EXPECT_EQ(Of(after, Phase::kSacUpdate), 0.0);
  EXPECT_EQ(PhaseName(Phase::kReplaySampling), "replay_sampling");
}

}  // namespace
}  // namespace srics::profile
