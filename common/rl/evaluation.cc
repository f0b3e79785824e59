#include "common/rl/evaluation.h"

#include <algorithm>

namespace srics::rl {

AttemptSchedule::AttemptSchedule(const SubgoalStructure& structure, SubgoalOrder order, EvaluationProtocol protocol,
                                 std::mt19937_64& rng)
    : protocol_(protocol), ordered_(structure.SubgoalEntities()) {
  if (ordered_.empty()) return;
  const int num_entities = structure.num_entities();
  const int m = static_cast<int>(ordered_.size());
  if (protocol_ == EvaluationProtocol::kReference) {
    slots_ = 2 * num_entities - 1;
    ordered_phase_ = order == SubgoalOrder::kDepth;
    first_phase_ = ordered_phase_ ? slots_ - m : slots_;
    if (ordered_phase_) {
      std::shuffle(ordered_.begin(), ordered_.end(), rng);
      // stable after the shuffle: equal depths keep their random order
      std::stable_sort(ordered_.begin(), ordered_.end(),
                       [&](int a, int b) { return structure.depth[a] > structure.depth[b]; });
    }
    position_ = std::uniform_int_distribution<size_t>(0, ordered_.size() - 1)(rng);
    return;
  }
  // kIndependentDraws, as it was (the same draws from the same generator): N - 1 draws
  first_phase_ = num_entities - 1;
  slots_ = first_phase_ + m;
  std::uniform_int_distribution<size_t> pick(0, ordered_.size() - 1);
  for (int i = 0; i < first_phase_; ++i) draws_.push_back(ordered_[pick(rng)]);
  std::shuffle(ordered_.begin(), ordered_.end(), rng);
  if (order == SubgoalOrder::kDepth) {
    std::stable_sort(ordered_.begin(), ordered_.end(),
                     [&](int a, int b) { return structure.depth[a] > structure.depth[b]; });
  }
}

std::optional<AttemptSchedule::Slot> AttemptSchedule::Next(const std::function<bool(int)>& solved) {
  if (next_slot_ >= slots_) return std::nullopt;
  if (protocol_ == EvaluationProtocol::kReference) return NextReference(solved);
  const int slot = next_slot_++;
  const int entity = slot < first_phase_ ? draws_[slot] : ordered_[slot - first_phase_];
  return Slot{entity, solved(entity)};
}

// gt_wrapper.py's step() at the end of each sub-task horizon, one slot at a time.
std::optional<AttemptSchedule::Slot> AttemptSchedule::NextReference(const std::function<bool(int)>& solved) {
  const size_t m = ordered_.size();
  auto end = [&]() -> std::optional<Slot> {
    next_slot_ = slots_;  // the episode is over: no slot is left
    return std::nullopt;
  };
  if (next_slot_ == 0) {  // the episode's first goal: drawn, not checked
    ++next_slot_;
    return Slot{ordered_[position_], false};
  }
  if (!walking_) origin_ = position_;
  // update_goal(): the ordered phase starts over at L[0], else the next in L
  position_ = ordered_phase_ && !walking_ && next_slot_ == first_phase_ ? 0 : (position_ + 1) % m;
  if (walking_ && position_ == origin_) return end();
  if (next_slot_ < first_phase_) {
    // passing over solved subgoals costs no slot; back at the origin, the episode is over
    while (solved(ordered_[position_])) {
      position_ = (position_ + 1) % m;
      if (position_ == origin_) return end();
    }
    ++next_slot_;
    return Slot{ordered_[position_], false};
  }
  // the ordered phase: a solved subgoal uses its slot up
  ++next_slot_;
  walking_ = solved(ordered_[position_]);
  return Slot{ordered_[position_], walking_};
}

SubgoalStructure AllEntitiesStructure(int num_entities) {
  SubgoalStructure structure;
  structure.ancestor_mask.assign(num_entities, 0);
  structure.depth.assign(num_entities, 1);
  return structure;
}

void EvaluationSummary::Add(const EpisodeMetrics& metrics, double threshold) {
  const size_t n = metrics.entity_distance.size();
  if (entity_distance.empty()) {
    entity_distance.assign(n, 0.0);
    subgoal_success.assign(n, 0.0);
  }
  const double previous = episodes;
  ++episodes;
  auto running_mean = [&](double mean, double value) { return (mean * previous + value) / episodes; };
  for (size_t i = 0; i < n && i < entity_distance.size(); ++i) {
    entity_distance[i] = running_mean(entity_distance[i], metrics.entity_distance[i]);
    subgoal_success[i] = running_mean(subgoal_success[i], metrics.entity_distance[i] < threshold ? 1.0 : 0.0);
  }
  avg_distance = running_mean(avg_distance, metrics.avg_distance);
  avg_object_distance = running_mean(avg_object_distance, metrics.avg_object_distance);
  success_rate = running_mean(success_rate, metrics.success ? 1.0 : 0.0);
  independent_solved += static_cast<uint32_t>(metrics.independent_solved);
  independent_undone += static_cast<uint32_t>(metrics.independent_undone);
  if (metrics.selectivity >= 0) {
    selectivity = (selectivity * selectivity_episodes + metrics.selectivity) / (selectivity_episodes + 1);
    ++selectivity_episodes;
  }
}

}  // namespace srics::rl
