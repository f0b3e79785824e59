#include "common/transport/graph_feed.h"

#include <spdlog/spdlog.h>

#include "common/transport/rl_convert.h"

namespace srics::transport {

std::optional<rl::GraphUpdate> GraphFeed::PollNewest() {
  InteractionGraph message;
  std::optional<rl::GraphUpdate> newest;
  while (reader_.Take(&message, std::chrono::milliseconds(0)) == TakeStatus::kSample) {
    if (message.version <= version_) continue;
    try {
      newest = FromMessage(message);
      version_ = newest->version;
    } catch (const std::invalid_argument& e) {
      ++rejected_;
      spdlog::warn("graph v{} refused: {}", message.version, e.what());
    }
  }
  return newest;
}

}  // namespace srics::transport
