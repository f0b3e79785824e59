#include "learner/episode_dedup.h"

#include <algorithm>

namespace srics::learner {

EpisodeDedup::EpisodeDedup(size_t window, size_t max_actors)
    : window_(std::max<size_t>(window, 1)), max_actors_(std::max<size_t>(max_actors, 1)) {}

bool EpisodeDedup::Seen(uint32_t actor_id, uint64_t episode_id) const {
  const auto it = actors_.find(actor_id);
  if (it == actors_.end()) return false;
  const Actor& a = it->second;
  if (a.forgot_any && episode_id <= a.forgotten_up_to) return true;
  return a.recent.count(episode_id) > 0;
}

void EpisodeDedup::Remember(uint32_t actor_id, uint64_t episode_id) {
  auto it = actors_.find(actor_id);
  if (it == actors_.end()) {
    if (actors_.size() >= max_actors_) {
      auto oldest = std::min_element(actors_.begin(), actors_.end(), [](const auto& x, const auto& y) {
        return x.second.last_use < y.second.last_use;
      });
      actors_.erase(oldest);
    }
    it = actors_.emplace(actor_id, Actor{}).first;
  }
  Actor& a = it->second;
  a.last_use = ++clock_;
  a.recent.insert(episode_id);
  while (a.recent.size() > window_) {
    const uint64_t lowest = *a.recent.begin();
    a.recent.erase(a.recent.begin());
    a.forgotten_up_to = a.forgot_any ? std::max(a.forgotten_up_to, lowest) : lowest;
    a.forgot_any = true;
  }
}

size_t EpisodeDedup::ids() const {
  size_t n = 0;
  for (const auto& [id, a] : actors_) n += a.recent.size();
  return n;
}

}  // namespace srics::learner
