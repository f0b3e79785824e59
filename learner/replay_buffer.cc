#include "learner/replay_buffer.h"

#include <algorithm>

#include "common/nn/serialize.h"

namespace srics::learner {
namespace {

uint64_t PayloadBytes(const rl::Episode& e) {
  return (e.states.size() + e.actions.size() + e.goal.size()) * sizeof(float);
}

// Version of the replay payload inside its checkpoint section.
// 2: episodes carry HAC's subgoal record; 1 (before it) still loads, without one.
constexpr uint32_t kReplayFormat = 2;
constexpr uint32_t kOldestReplayFormat = 1;

void PutEpisode(nn::ByteWriter& w, const rl::Episode& e) {
  w.Put<int32_t>(e.layout.num_entities);
  w.Put<int32_t>(e.layout.num_kinds);
  w.Put<uint8_t>(e.layout.velocities ? 1 : 0);
  w.PutVector(e.entity_kinds);
  w.Put<int32_t>(e.num_steps);
  w.Put<int32_t>(e.action_dim);
  w.PutVector(e.states);
  w.PutVector(e.actions);
  w.Put<int32_t>(e.subgoal_entity);
  w.PutVector(e.goal);
  w.Put<uint64_t>(e.ancestor_mask);
  w.Put<int32_t>(static_cast<int32_t>(e.mode));
  w.Put<uint32_t>(e.actor_id);
  w.Put<uint64_t>(e.episode_id);
  w.Put<uint64_t>(e.policy_version);
  w.Put<uint64_t>(e.graph_version);
  w.PutVector(e.subgoal_starts);
  w.PutVector(e.subgoals);
  w.PutVector(e.subgoal_tests);
}

rl::Episode GetEpisode(nn::ByteReader& r, uint32_t format) {
  rl::Episode e;
  e.layout.num_entities = r.Get<int32_t>();
  e.layout.num_kinds = r.Get<int32_t>();
  e.layout.velocities = r.Get<uint8_t>() != 0;
  e.entity_kinds = r.GetVector<uint16_t>();
  e.num_steps = r.Get<int32_t>();
  e.action_dim = r.Get<int32_t>();
  e.states = r.GetVector<float>();
  e.actions = r.GetVector<float>();
  e.subgoal_entity = r.Get<int32_t>();
  e.goal = r.GetVector<float>();
  e.ancestor_mask = r.Get<uint64_t>();
  e.mode = static_cast<rl::EpisodeMode>(r.Get<int32_t>());
  e.actor_id = r.Get<uint32_t>();
  e.episode_id = r.Get<uint64_t>();
  e.policy_version = r.Get<uint64_t>();
  e.graph_version = r.Get<uint64_t>();
  if (format >= 2) {
    e.subgoal_starts = r.GetVector<uint16_t>();
    e.subgoals = r.GetVector<float>();
    e.subgoal_tests = r.GetVector<uint8_t>();
  }
  return e;
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

std::string ReplayBuffer::Serialize() const {
  nn::ByteWriter w;
  w.Put<uint32_t>(kReplayFormat);
  w.Put<uint64_t>(next_start_);
  w.Put<uint64_t>(inserted_total_);
  w.Put<uint64_t>(episodes_.size());
  for (const rl::Episode& e : episodes_) PutEpisode(w, e);
  return w.Take();
}

void ReplayBuffer::Restore(const std::string& bytes, const rl::EpisodeLimits& limits, const std::string& what) {
  nn::ByteReader r(bytes, what);
  const auto format = r.Get<uint32_t>();
  if (format < kOldestReplayFormat || format > kReplayFormat)
    throw nn::CheckpointError(what + ": replay format " + std::to_string(format) + " (this build reads " +
                              std::to_string(kOldestReplayFormat) + " to " + std::to_string(kReplayFormat) + ")");
  const auto next_start = r.Get<uint64_t>();
  const auto inserted_total = r.Get<uint64_t>();
  const auto count = r.Get<uint64_t>();
  std::deque<rl::Episode> episodes;
  uint64_t transitions = 0;
  for (uint64_t i = 0; i < count; ++i) {
    episodes.push_back(GetEpisode(r, format));
    if (const std::string problem = rl::ValidateEpisode(episodes.back(), limits); !problem.empty())
      throw nn::CheckpointError(what + ": replay episode " + std::to_string(i) + ": " + problem);
    transitions += static_cast<uint64_t>(episodes.back().num_steps);
  }
  if (!r.done()) throw nn::CheckpointError(what + ": " + std::to_string(r.remaining()) + " bytes after the replay");
  if (transitions > next_start || next_start > inserted_total)
    throw nn::CheckpointError(what + ": replay counters (" + std::to_string(next_start) + ", " +
                              std::to_string(inserted_total) + ") below its " + std::to_string(transitions) +
                              " stored transitions");
  // the running start index of each episode, counted back from the end
  std::deque<uint64_t> start;
  uint64_t at = next_start;
  for (auto it = episodes.rbegin(); it != episodes.rend(); ++it) {
    at -= static_cast<uint64_t>(it->num_steps);
    start.push_front(at);
  }
  episodes_ = std::move(episodes);
  start_ = std::move(start);
  next_start_ = next_start;
  inserted_total_ = inserted_total;
  transitions_ = transitions;
  payload_bytes_ = 0;
  for (const rl::Episode& e : episodes_) payload_bytes_ += PayloadBytes(e);
  // a smaller capacity than the saved run's: the oldest leave, as on insert
  while (episodes_.size() > 1 && transitions_ > capacity_) {
    transitions_ -= static_cast<uint64_t>(episodes_.front().num_steps);
    payload_bytes_ -= PayloadBytes(episodes_.front());
    episodes_.pop_front();
    start_.pop_front();
  }
}

int ReplayBuffer::max_entities() const {
  int n = 0;
  for (const auto& e : episodes_) n = std::max(n, e.layout.num_entities);
  return n;
}

}  // namespace srics::learner
