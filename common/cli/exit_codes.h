#pragma once
// The exit codes of every SRICS-DDS program, in one place: scripts and the launcher's
// supervisor tell a failure a restart may cure (1) from one it cannot (2, 65).

namespace srics {

// finished (a run: budget, learner or wall time)
inline constexpr int kExitDone = 0;
// failed; a restart may help
inline constexpr int kExitFailed = 1;
// bad command line, config or input file; a live run of this run id
inline constexpr int kExitUsage = 2;
// srics-monitor --once: no sample arrived while it waited
inline constexpr int kExitNothingReceived = 3;
// state on disk a role must not start over from (unusable checkpoints; EX_DATAERR)
inline constexpr int kExitUnusableState = 65;
// stopped by SIGINT/SIGTERM
inline constexpr int kExitInterrupted = 130;

}  // namespace srics
