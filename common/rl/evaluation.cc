#include "common/rl/evaluation.h"

#include <algorithm>

namespace srics::rl {

AttemptSchedule::AttemptSchedule(const SubgoalStructure& structure, SubgoalOrder order,
                                 EvaluationProtocol protocol, std::mt19937_64& rng)
    : protocol_(protocol), ordered_(structure.SubgoalEntities()) {
  if (ordered_.empty()) return;
  const int num_entities = structure.num_entities();
  const int m = static_cast<int>(ordered_.size());
  // kIndependentDraws: N - 1 draws whatever m is (2N - 1 slots only when every entity has a subgoal)
  first_phase_ = protocol_ == EvaluationProtocol::kReference ? 2 * num_entities - 1 - m : num_entities - 1;
  slots_ = first_phase_ + m;
  if (protocol_ == EvaluationProtocol::kIndependentDraws) {
    std::uniform_int_distribution<size_t> pick(0, ordered_.size() - 1);
    for (int i = 0; i < first_phase_; ++i) draws_.push_back(ordered_[pick(rng)]);
  }
  std::shuffle(ordered_.begin(), ordered_.end(), rng);
  if (order == SubgoalOrder::kDepth) {
    // stable after the shuffle: equal depths keep their random order
    std::stable_sort(ordered_.begin(), ordered_.end(),
                     [&](int a, int b) { return structure.depth[a] > structure.depth[b]; });
  }
  if (protocol_ == EvaluationProtocol::kReference)
    cycle_ = std::uniform_int_distribution<size_t>(0, ordered_.size() - 1)(rng);
}

std::optional<AttemptSchedule::Slot> AttemptSchedule::Next(const std::function<bool(int)>& solved) {
  if (next_slot_ >= slots_) return std::nullopt;
  const int slot = next_slot_++;
  if (slot >= first_phase_) {
    const int entity = ordered_[slot - first_phase_];
    return Slot{entity, solved(entity)};
  }
  if (protocol_ == EvaluationProtocol::kIndependentDraws) return Slot{draws_[slot], solved(draws_[slot])};
  for (size_t tried = 0; tried < ordered_.size(); ++tried) {
    const int entity = ordered_[cycle_];
    cycle_ = (cycle_ + 1) % ordered_.size();
    if (!solved(entity)) return Slot{entity, false};
  }
  // every subgoal solved: the reference ends the episode here
  next_slot_ = slots_;
  return std::nullopt;
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
    subgoal_success[i] =
        running_mean(subgoal_success[i], metrics.entity_distance[i] < threshold ? 1.0 : 0.0);
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
