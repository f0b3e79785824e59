#pragma once
// The exit codes of every SRICS-DDS program, in one place: scripts and the launcher's
// supervisor tell a failure a restart may cure (1) from one it cannot (2, 65).

namespace srics {

inline constexpr int kExitDone = 0;    // finished (a run: budget, learner or wall time)
inline constexpr int kExitFailed = 1;  // failed; a restart may help
inline constexpr int kExitUsage = 2;   // bad command line, config or input file; a live run of this run id
inline constexpr int kExitUnusableState =
    65;                                       // state on disk it must not start over (unusable checkpoints; EX_DATAERR)
inline constexpr int kExitInterrupted = 130;  // stopped by SIGINT/SIGTERM

}  // namespace srics
