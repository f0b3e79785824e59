#pragma once
// The evaluation protocol: a full goal split into subgoals, attempted in depth order
// (docs/method.md section 3), and the metrics gathered over evaluation episodes.

#include <random>
#include <vector>

#include "common/rl/graph.h"

namespace srics::rl {

enum class SubgoalOrder {
  kDepth,   // SRICS: deepest first, the driven entity (arm) last, ties in random order
  kRandom,  // SMORL and the no-order ablation: a random permutation
};

// The entities to attempt, in order: 2N - 1 attempts for N entities (7 for the arm and 3
// pucks). The first N - 1 are uniformly random subgoal entities; the last ones are every
// subgoal entity once, in `order`. Entities without a subgoal never appear. The runner skips
// an attempt whose subgoal is already solved when it starts.
std::vector<int> EvaluationSchedule(const SubgoalStructure& structure, SubgoalOrder order,
                                    std::mt19937_64& rng);

// A structure where every entity is a subgoal of depth 1 with no ancestors (SMORL's view:
// it knows no graph).
SubgoalStructure AllEntitiesStructure(int num_entities);

// Final-step metrics of one evaluation episode.
struct EpisodeMetrics {
  std::vector<double> entity_distance;  // N
  double avg_distance = 0;              // arm and objects
  double avg_object_distance = 0;       // objects only
  bool success = false;
  double selectivity = -1;              // mean selectivity over the episode, -1 if undefined
};

// Means over evaluation episodes (what EvalResult carries).
struct EvaluationSummary {
  int episodes = 0;
  std::vector<double> entity_distance;  // mean final distance per entity
  std::vector<double> subgoal_success;  // fraction of episodes entity i ended within threshold
  double avg_distance = 0;
  double avg_object_distance = 0;
  double success_rate = 0;
  double selectivity = 0;               // mean over episodes where it was defined
  int selectivity_episodes = 0;

  // Folds one episode in; `threshold` decides per-entity success.
  void Add(const EpisodeMetrics& metrics, double threshold);
};

}  // namespace srics::rl
