#include "learner/replay_buffer.h"

#include <algorithm>

namespace srics::learner {
namespace {

uint64_t PayloadBytes(const rl::Episode& e) {
  return (e.states.size() + e.actions.size() + e.goal.size()) * sizeof(float);
}

}  // namespace

ReplayBuffer::ReplayBuffer(uint64_t capacity_transitions) : capacity_(capacity_transitions) {}

uint64_t ReplayBuffer::Insert(rl::Episode episode) {
  const uint64_t length = episode.num_steps;
  uint64_t evicted = 0;
  while (!episodes_.empty() && transitions_ + length > capacity_) {
    const uint64_t oldest = episodes_.front().num_steps;
    transitions_ -= oldest;
    evicted += oldest;
    payload_bytes_ -= PayloadBytes(episodes_.front());
    episodes_.pop_front();
    start_.pop_front();
  }
  payload_bytes_ += PayloadBytes(episode);
  episodes_.push_back(std::move(episode));
  start_.push_back(next_start_);
  next_start_ += length;
  transitions_ += length;
  inserted_total_ += length;
  return evicted;
}

ReplayBuffer::TransitionRef ReplayBuffer::Sample(std::mt19937_64& rng) const {
  std::uniform_int_distribution<uint64_t> pick(start_.front(), next_start_ - 1);
  const uint64_t index = pick(rng);
  // the last episode starting at or before `index`
  const auto it = std::upper_bound(start_.begin(), start_.end(), index) - 1;
  const size_t slot = static_cast<size_t>(it - start_.begin());
  return {&episodes_[slot], static_cast<int>(index - *it)};
}

int ReplayBuffer::max_entities() const {
  int n = 0;
  for (const auto& e : episodes_) n = std::max(n, e.layout.num_entities);
  return n;
}

}  // namespace srics::learner
