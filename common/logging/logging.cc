#include "common/logging/logging.h"

#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>

#include <filesystem>
#include <stdexcept>
#include <vector>

namespace srics::logging {

std::shared_ptr<spdlog::logger> SetUpLogger(const std::string& name, const LogOptions& options) {
  const spdlog::level::level_enum level = spdlog::level::from_str(options.level);
  // from_str maps anything unknown to "off"; only "off" itself may mean off
  if (level == spdlog::level::off && options.level != "off")
    throw std::invalid_argument("unknown log level '" + options.level +
                                "' (expected trace, debug, info, warn, error or off)");
  std::vector<spdlog::sink_ptr> sinks;
  sinks.push_back(std::make_shared<spdlog::sinks::stderr_color_sink_mt>());
  if (!options.file.empty()) {
    std::filesystem::create_directories(std::filesystem::path(options.file).parent_path());
    sinks.push_back(std::make_shared<spdlog::sinks::basic_file_sink_mt>(options.file));
  }
  spdlog::drop(name);
  auto logger = std::make_shared<spdlog::logger>(name, sinks.begin(), sinks.end());
  logger->set_level(level);
  logger->set_pattern("%Y-%m-%d %H:%M:%S.%e [%n] %^%l%$ %v");
  // warnings at once; everything else within a second, so logs can be followed live
  logger->flush_on(spdlog::level::warn);
  spdlog::flush_every(std::chrono::seconds(1));
  spdlog::register_logger(logger);
  spdlog::set_default_logger(logger);
  return logger;
}

bool RateLimiter::Allow(uint64_t* suppressed) {
  const int64_t now =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
  int64_t next = next_allowed_ns_.load();
  if (now >= next && next_allowed_ns_.compare_exchange_strong(
                         next, now + std::chrono::duration_cast<std::chrono::nanoseconds>(interval_).count())) {
    if (suppressed) *suppressed = suppressed_.exchange(0);
    return true;
  }
  suppressed_.fetch_add(1);
  return false;
}

}  // namespace srics::logging
