#include "common/transport/shutdown.h"

#include <dds/dds.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <thread>

#include "common/transport/errors.h"

namespace srics::transport {
namespace {

// The self-pipe between the signal handler and the watcher thread.
int g_pipe[2] = {-1, -1};

}  // namespace

Shutdown& Shutdown::Process() {
  // never destroyed: signal handlers and detached threads may use it during exit
  static Shutdown* instance = new Shutdown();
  return *instance;
}

void Shutdown::OnSignal(int signal_number) {
  const int saved_errno = errno;
  Shutdown& shutdown = Process();  // constructed before the handler was installed
  if (shutdown.requested_.exchange(true)) {
    // second signal while stopping: give the user the default action (terminate)
    std::signal(signal_number, SIG_DFL);
    std::raise(signal_number);
  } else if (g_pipe[1] >= 0) {
    const char byte = 1;
    [[maybe_unused]] ssize_t n = write(g_pipe[1], &byte, 1);
  }
  errno = saved_errno;
}

void Shutdown::InstallSignalHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    Process();
    if (pipe2(g_pipe, O_CLOEXEC) != 0) throw std::runtime_error("shutdown: pipe2 failed");
    // the watcher does the DDS calls a signal handler must not do
    std::thread([] {
      char byte;
      while (true) {
        const ssize_t n = read(g_pipe[0], &byte, 1);
        if (n == 1) break;
        if (n < 0 && errno == EINTR) continue;
        return;
      }
      Process().Request();
    }).detach();
    struct sigaction action = {};
    action.sa_handler = &Shutdown::OnSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
  });
}

void Shutdown::Request() {
  requested_.store(true, std::memory_order_release);
  std::lock_guard<std::mutex> lock(mutex_);
  for (int32_t guard : guards_) dds_set_guardcondition(guard, true);
}

void Shutdown::Register(int32_t guard) {
  std::lock_guard<std::mutex> lock(mutex_);
  guards_.insert(guard);
  if (requested()) dds_set_guardcondition(guard, true);
}

void Shutdown::Unregister(int32_t guard) {
  std::lock_guard<std::mutex> lock(mutex_);
  guards_.erase(guard);
}

}  // namespace srics::transport
