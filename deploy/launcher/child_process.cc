#include "deploy/launcher/child_process.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stdexcept>
#include <thread>
#include <utility>

namespace srics::launcher {
namespace {

// An owned file descriptor.
class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  ~Fd() { Reset(); }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }
  // Takes ownership of `fd` (closing what it held).
  void Reset(int fd) {
    Reset();
    fd_ = fd;
  }
  void Reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

ExitStatus FromWaitStatus(int status) {
  if (WIFSIGNALED(status)) return {true, WTERMSIG(status)};
  return {false, WIFEXITED(status) ? WEXITSTATUS(status) : -1};
}

// In the child between fork and exec: async-signal-safe calls only.
[[noreturn]] void ExecChild(char* const* argv, int output_fd, int error_pipe, const SpawnOptions& options,
                            pid_t parent) {
  if (options.parent_death_signal != 0) {
    prctl(PR_SET_PDEATHSIG, options.parent_death_signal);
    if (getppid() != parent) _exit(127);  // the parent already died
  }
  if (options.own_process_group) setpgid(0, 0);
  // default dispositions and an empty mask (the launcher's handlers and blocks stay behind)
  struct sigaction action;
  memset(&action, 0, sizeof action);
  action.sa_handler = SIG_DFL;
  for (int s : {SIGINT, SIGTERM, SIGPIPE, SIGCHLD, SIGHUP, SIGQUIT}) sigaction(s, &action, nullptr);
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  const int null_fd = open("/dev/null", O_RDONLY);
  if (null_fd >= 0) dup2(null_fd, STDIN_FILENO);
  if (output_fd >= 0) {
    dup2(output_fd, STDOUT_FILENO);
    dup2(output_fd, STDERR_FILENO);
  }
  execv(argv[0], argv);
  const int error = errno;
  ssize_t ignored = write(error_pipe, &error, sizeof error);
  (void)ignored;
  _exit(127);
}

}  // namespace

std::string ExitStatus::Describe() const {
  if (!signaled) return "exit code " + std::to_string(code);
  const char* name = strsignal(code);
  return "signal " + std::to_string(code) + (name ? std::string(" (") + name + ")" : std::string());
}

ChildProcess ChildProcess::Spawn(const std::vector<std::string>& argv, const SpawnOptions& options) {
  if (argv.empty()) throw std::invalid_argument("ChildProcess::Spawn: empty argv");
  // everything the child needs is prepared before fork: the child may not allocate
  std::vector<std::string> args = argv;
  std::vector<char*> c_argv;
  for (std::string& a : args) c_argv.push_back(a.data());
  c_argv.push_back(nullptr);

  Fd output;
  if (!options.output_file.empty()) {
    output.Reset(open(options.output_file.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644));
    if (output.get() < 0) throw std::runtime_error("cannot open " + options.output_file + ": " + strerror(errno));
  }
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe2: ") + strerror(errno));
  Fd read_end(pipe_fds[0]), write_end(pipe_fds[1]);

  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + strerror(errno));
  if (pid == 0) ExecChild(c_argv.data(), output.get(), write_end.get(), options, parent);

  ChildProcess child;
  child.pid_ = pid;
  write_end.Reset();
  // the pipe closes on a successful exec; otherwise it carries errno
  int error = 0;
  ssize_t n;
  do {
    n = read(read_end.get(), &error, sizeof error);
  } while (n < 0 && errno == EINTR);
  if (n == sizeof error) {
    child.Kill();  // reap the failed child
    throw std::runtime_error("cannot execute " + argv[0] + ": " + strerror(error));
  }
  return child;
}

ChildProcess::~ChildProcess() { Release(); }

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : pid_(std::exchange(other.pid_, 0)), exit_(std::exchange(other.exit_, std::nullopt)) {}

ChildProcess& ChildProcess::operator=(ChildProcess&& other) noexcept {
  if (this != &other) {
    Release();
    pid_ = std::exchange(other.pid_, 0);
    exit_ = std::exchange(other.exit_, std::nullopt);
  }
  return *this;
}

void ChildProcess::Release() {
  if (running()) Kill();
  pid_ = 0;
  exit_.reset();
}

std::optional<ExitStatus> ChildProcess::Poll() {
  if (pid_ <= 0 || exit_) return exit_;
  int status = 0;
  pid_t r;
  do {
    r = waitpid(pid_, &status, WNOHANG);
  } while (r < 0 && errno == EINTR);
  if (r == pid_)
    exit_ = FromWaitStatus(status);
  else if (r < 0)
    exit_ = ExitStatus{false, -1};  // ECHILD: reaped elsewhere; treat as gone
  return exit_;
}

std::optional<ExitStatus> ChildProcess::WaitFor(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!Poll() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  return exit_;
}

bool ChildProcess::Signal(int signal) {
  if (!running()) return false;
  return ::kill(pid_, signal) == 0;
}

ExitStatus ChildProcess::Kill() {
  if (pid_ <= 0) return {false, -1};
  if (exit_) return *exit_;
  ::kill(pid_, SIGKILL);
  int status = 0;
  pid_t r;
  do {
    r = waitpid(pid_, &status, 0);
  } while (r < 0 && errno == EINTR);
  exit_ = r == pid_ ? FromWaitStatus(status) : ExitStatus{true, SIGKILL};
  return *exit_;
}

}  // namespace srics::launcher
