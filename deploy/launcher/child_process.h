#pragma once
// One child process, owned: started with fork/exec, reaped with waitpid. The destructor of a
// child still running kills (SIGKILL) and reaps it, so no path leaves a zombie or an orphan
// behind.

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace srics::launcher {

// How a child ended.
struct ExitStatus {
  bool signaled = false;  // killed by a signal (then `code` is the signal number)
  int code = 0;           // exit code, or the signal number
  bool success() const { return !signaled && code == 0; }
  // "exit code 3", "signal 9 (Killed)"
  std::string Describe() const;
};

struct SpawnOptions {
  std::string output_file;  // stdout and stderr are appended here ("" = inherit the parent's)
  // Own process group: a Ctrl-C on the terminal reaches only the launcher, which then sends
  // each child exactly one SIGINT (a second one would force-quit a role mid-checkpoint).
  bool own_process_group = true;
  // Linux: the child gets this signal if the launcher dies without stopping it (0 = none).
  int parent_death_signal = 15;  // SIGTERM
};

class ChildProcess {
 public:
  // Starts argv[0] (a path) with argv. Throws std::runtime_error when the program cannot be
  // executed (the exec error is reported back through a close-on-exec pipe) or the output
  // file cannot be opened.
  static ChildProcess Spawn(const std::vector<std::string>& argv, const SpawnOptions& options = {});

  ChildProcess() = default;
  ~ChildProcess();
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&& other) noexcept;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  // True from Spawn until it was reaped.
  bool running() const { return pid_ > 0 && !exit_; }
  // The exit status once reaped.
  const std::optional<ExitStatus>& exit_status() const { return exit_; }

  // Reaps the child if it has ended (non-blocking). Returns the exit status once ended.
  std::optional<ExitStatus> Poll();
  // Waits up to `timeout` for the child to end.
  std::optional<ExitStatus> WaitFor(std::chrono::milliseconds timeout);
  // Sends `signal` (no-op once reaped). False if kill() failed.
  bool Signal(int signal);
  // SIGKILL and blocking reap (no-op once reaped).
  ExitStatus Kill();

 private:
  void Release();
  pid_t pid_ = 0;
  std::optional<ExitStatus> exit_;
};

}  // namespace srics::launcher
