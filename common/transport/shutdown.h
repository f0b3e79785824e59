#pragma once
// A shutdown request that wakes every blocked take and write of the participants bound to
// it. One process-wide instance is triggered by SIGINT/SIGTERM once
// InstallSignalHandlers() ran:
//
//   srics::transport::Shutdown::InstallSignalHandlers();
//   Participant participant(config.transport);          // bound to Shutdown::Process()
//   while (reader.Take(&episode, 1s) != TakeStatus::kShutdown) { ... }

#include <atomic>
#include <cstdint>
#include <mutex>
#include <set>

namespace srics::transport {

class Shutdown {
 public:
  Shutdown() = default;
  Shutdown(const Shutdown&) = delete;
  Shutdown& operator=(const Shutdown&) = delete;

  // The process-wide instance (the one signals trigger and participants use by default).
  static Shutdown& Process();

  // Makes SIGINT and SIGTERM request Process() shutdown. The handler only stores an atomic
  // flag and writes one byte to a self-pipe (both async-signal-safe); a watcher thread then
  // triggers the DDS guard conditions, which is not safe inside a handler. A second signal
  // while shutting down restores the default action and re-raises (forced exit).
  // Idempotent; call it early in main, before other threads start.
  static void InstallSignalHandlers();

  // Requests shutdown: sets the flag and triggers every registered guard condition, so
  // blocked takes and back-pressure retries return at once. Thread-safe; idempotent.
  void Request();

  // True once Request() ran or (for Process()) a signal arrived.
  bool requested() const { return requested_.load(std::memory_order_acquire); }
  // The flag itself, for loops that poll a std::atomic<bool> (set once, never cleared).
  const std::atomic<bool>& flag() const { return requested_; }

  // Internal, for Participant: guard conditions (DDS entity handles) to trigger on Request().
  // Registering after a request triggers the guard immediately.
  void Register(int32_t guard);
  void Unregister(int32_t guard);

 private:
  // the SIGINT/SIGTERM handler: async-signal-safe work only
  static void OnSignal(int signal_number);

  std::atomic<bool> requested_{false};
  std::mutex mutex_;
  std::set<int32_t> guards_;
};

}  // namespace srics::transport
