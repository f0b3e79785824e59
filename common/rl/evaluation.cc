#include "common/rl/evaluation.h"

#include <algorithm>

namespace srics::rl {

std::vector<int> EvaluationSchedule(const SubgoalStructure& structure, SubgoalOrder order,
                                    std::mt19937_64& rng) {
  std::vector<int> entities = structure.SubgoalEntities();
  std::vector<int> schedule;
  if (entities.empty()) return schedule;
  const int num_entities = structure.num_entities();
  std::uniform_int_distribution<size_t> pick(0, entities.size() - 1);
  for (int i = 0; i < num_entities - 1; ++i) schedule.push_back(entities[pick(rng)]);
  std::shuffle(entities.begin(), entities.end(), rng);
  if (order == SubgoalOrder::kDepth) {
    // stable after the shuffle: equal depths keep their random order
    std::stable_sort(entities.begin(), entities.end(), [&](int a, int b) {
      return structure.depth[a] > structure.depth[b];
    });
  }
  schedule.insert(schedule.end(), entities.begin(), entities.end());
  return schedule;
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
  if (metrics.selectivity >= 0) {
    selectivity = (selectivity * selectivity_episodes + metrics.selectivity) / (selectivity_episodes + 1);
    ++selectivity_episodes;
  }
}

}  // namespace srics::rl
