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
      ReceivedGraph g = FromMessage(message);
      version_ = g.version;
      newest = rl::GraphUpdate{g.version, std::move(g.graph), std::move(g.structure)};
    } catch (const std::invalid_argument& e) {
      ++rejected_;
      spdlog::warn("graph v{} refused: {}", message.version, e.what());
    }
  }
  return newest;
}

}  // namespace srics::transport
