#pragma once
// Replay of whole episodes (HER needs the future of each transition). Capacity counts
// transitions; when full, whole episodes leave oldest first. Each state is stored once, in
// its episode: T transitions cost T + 1 states, not 2T.
//
// Not thread-safe: the learner loop owns it (ingest and sampling happen on one thread).

#include <cstdint>
#include <deque>
#include <random>
#include <string>

#include "common/rl/episode.h"

namespace srics::learner {

class ReplayBuffer {
 public:
  explicit ReplayBuffer(uint64_t capacity_transitions);

  // Takes the episode (already validated). An episode longer than the whole capacity is
  // stored alone. Returns how many transitions were evicted to make room.
  uint64_t Insert(rl::Episode episode);

  // A uniformly random transition over everything stored: episode and time step t
  // (the transition goes from state t to state t + 1). Precondition: !empty().
  struct TransitionRef {
    const rl::Episode* episode;
    int t;
  };
  TransitionRef Sample(std::mt19937_64& rng) const;

  uint64_t transitions() const { return transitions_; }
  uint64_t episodes() const { return episodes_.size(); }
  uint64_t capacity() const { return capacity_; }
  bool empty() const { return transitions_ == 0; }
  uint64_t inserted_total() const { return inserted_total_; }
  // Bytes held by states and actions (what the capacity bound is about).
  uint64_t payload_bytes() const { return payload_bytes_; }
  // Largest entity count among stored episodes (batches pad to it).
  int max_entities() const;
  const std::deque<rl::Episode>& contents() const { return episodes_; }

  // Everything stored (the episodes in insertion order and the running counters) as the
  // bytes of a checkpoint section.
  std::string Serialize() const;
  // Replaces the contents with what Serialize wrote. Every episode must pass
  // rl::ValidateEpisode against `limits` (a checkpoint of another environment is refused).
  // A smaller capacity than the saved contents drops the oldest episodes, as Insert would.
  // Throws nn::CheckpointError naming `what` on a truncated or malformed payload, leaving
  // the buffer as it was.
  void Restore(const std::string& bytes, const rl::EpisodeLimits& limits, const std::string& what);

 private:
  uint64_t capacity_;
  std::deque<rl::Episode> episodes_;
  // start_[i]: running transition index at which episodes_[i] begins (monotone, never reset)
  std::deque<uint64_t> start_;
  uint64_t next_start_ = 0;
  uint64_t transitions_ = 0;
  uint64_t inserted_total_ = 0;
  uint64_t payload_bytes_ = 0;
};

}  // namespace srics::learner
