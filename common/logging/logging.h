#pragma once
// One named spdlog logger per role ("actor-3", "learner", "graph"), a console sink on stderr
// and optionally a file sink in the run folder, and a rate limiter for hot-path warnings.

#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>

namespace srics::logging {

struct LogOptions {
  std::string level = "info";  // trace, debug, info, warn, error, off
  std::string file;            // empty = console only
};

// Creates (or replaces) the logger `name`, makes it the default, and returns it.
// Throws std::invalid_argument for an unknown level.
std::shared_ptr<spdlog::logger> SetUpLogger(const std::string& name, const LogOptions& options);

// Lets a warning through at most once per interval; counts what it held back so the next
// message can say "(N more suppressed)". Thread-safe.
class RateLimiter {
 public:
  explicit RateLimiter(std::chrono::milliseconds interval) : interval_(interval) {}
  // True when a message may be logged now; *suppressed receives how many were held back.
  bool Allow(uint64_t* suppressed);

 private:
  std::chrono::milliseconds interval_;
  std::atomic<int64_t> next_allowed_ns_{0};
  std::atomic<uint64_t> suppressed_{0};
};

}  // namespace srics::logging
