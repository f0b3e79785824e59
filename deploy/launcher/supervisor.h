#pragma once
// Supervises named child processes: starts them, restarts the ones that fail (exit by a signal
// or with a non-zero code) after an exponential backoff, and stops them all: the stop signal
// (SIGINT) to each, a wait, SIGKILL for what is left after the timeout, every child reaped.
//
//   Supervisor supervisor({.backoff = {.initial = 1s}});
//   supervisor.Add({.name = "actor-0", .argv = {bin, "cfg.yaml", "--id", "0"}});
//   supervisor.StartAll();
//   while (...) { supervisor.Tick(); sleep; }
//   supervisor.StopAll();
//
// Threading: one thread. Nothing here knows about SRICS roles: tests drive it with stand-in
// programs.

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "deploy/launcher/child_process.h"

namespace srics::launcher {

using SteadyClock = std::chrono::steady_clock;

enum class RestartPolicy {
  kNever,      // whatever the exit, it stays down
  kOnFailure,  // restarted after a signal or a non-zero exit; exit code 0 means done
};

struct ChildSpec {
  std::string name;               // unique, e.g. "actor-1"
  std::vector<std::string> argv;  // argv[0]: path of the program
  std::string output_file;        // stdout + stderr appended here ("" = the launcher's)
  RestartPolicy restart = RestartPolicy::kOnFailure;
  int max_restarts = -1;  // restarts allowed in all (-1 = no limit)
  // exit codes after which a restart cannot help (the role programs' 2: a bad config or
  // command line; 65: state on disk it must not start over, e.g. unusable checkpoints): the
  // child is failed at once
  std::vector<int> final_exit_codes;
};

struct BackoffPolicy {
  std::chrono::milliseconds initial{1000};       // delay before the first restart
  double factor = 2.0;                           // each consecutive failure multiplies it
  std::chrono::milliseconds max{30000};          // cap
  std::chrono::milliseconds reset_after{60000};  // a child that ran this long starts over at `initial`
};

struct SupervisorOptions {
  BackoffPolicy backoff;
  std::chrono::milliseconds stop_timeout{10000};     // SIGINT -> SIGKILL
  int stop_signal = 2;                               // SIGINT
  SpawnOptions spawn;                                // output_file is taken from each ChildSpec
  std::function<void(const std::string&)> on_event;  // "actor-1 ended: signal 9 ...; restart in 1.0s"
};

enum class ChildPhase {
  kNotStarted,
  kRunning,
  kWaitingToRestart,  // failed; restarts at restart_at
  kFinished,          // exited with code 0, or stopped by StopAll
  kFailed,            // failed and will not be restarted (policy kNever or max_restarts reached)
};
const char* ChildPhaseName(ChildPhase phase);

// What the supervisor knows about one child.
struct ChildStatus {
  std::string name;
  ChildPhase phase = ChildPhase::kNotStarted;
  int pid = 0;            // 0 unless running
  uint32_t restarts = 0;  // restarts done so far
  uint32_t consecutive_failures = 0;
  std::optional<ExitStatus> last_exit;
  SteadyClock::time_point started_at;  // of the current or last incarnation
  SteadyClock::time_point restart_at;  // when kWaitingToRestart
};

class Supervisor {
 public:
  explicit Supervisor(SupervisorOptions options = {});
  // Stops whatever still runs (StopAll).
  ~Supervisor();
  Supervisor(const Supervisor&) = delete;
  Supervisor& operator=(const Supervisor&) = delete;

  // Registers a child (not started yet); returns its index. Throws std::invalid_argument for an
  // empty argv or a duplicate name.
  size_t Add(ChildSpec spec);
  // Starts every child not started yet. Throws std::runtime_error when a program cannot be
  // executed (nothing is left running then: children already started are stopped).
  void StartAll();
  // Reaps ended children, schedules restarts (backoff) and performs those that are due.
  // Returns the indices of children that ended for good in this call (kFinished or kFailed).
  std::vector<size_t> Tick();
  // Sends the stop signal to every running child (and cancels pending restarts), waits up to
  // stop_timeout, SIGKILLs the rest and reaps all. True when every child ended before the
  // timeout. Stopped children end in kFinished (or kFailed if they had to be killed).
  bool StopAll();
  // The same for one child (e.g. to stop a finished run's other roles selectively).
  bool Stop(size_t index);
  // SIGKILLs a running child that is hung (`why` goes into the event); the next Tick sees it
  // end by a signal and restarts it under its policy. False if it was not running.
  bool Kill(size_t index, const std::string& why);

  size_t size() const { return children_.size(); }
  const ChildStatus& status(size_t index) const { return children_[index].status; }
  std::optional<size_t> Find(const std::string& name) const;
  // Sum of restarts over all children.
  uint32_t total_restarts() const;
  // True when no child is running or waiting to restart.
  bool AllDown() const;

  // The delay before restart number `consecutive_failures` (1 = first failure).
  static std::chrono::milliseconds BackoffDelay(const BackoffPolicy& policy, uint32_t consecutive_failures);

 private:
  struct Child {
    ChildSpec spec;
    ChildProcess process;
    ChildStatus status;
  };
  void Event(const std::string& text) const;
  // Starts (or restarts) one child; false if it could not be executed.
  bool Launch(Child* child, std::string* error);
  bool StopSome(const std::vector<size_t>& indices);

  SupervisorOptions options_;
  std::vector<Child> children_;
};

}  // namespace srics::launcher
