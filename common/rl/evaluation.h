#pragma once
// The evaluation protocol: a full goal split into subgoals, attempted in depth order
// (docs/method.md section 3), and the metrics gathered over evaluation episodes.

#include <cstdint>
#include <functional>
#include <optional>
#include <random>
#include <vector>

#include "common/rl/graph.h"

namespace srics::rl {

enum class SubgoalOrder {
  kDepth,   // SRICS: deepest first, the driven entity (arm) last, ties in random order
  kRandom,  // SMORL and the no-order ablation: a random permutation
};

// How the attempts of one evaluation episode are chosen. The last m slots are every subgoal
// entity once, in the method's order (m = the subgoal entities).
enum class EvaluationProtocol {
  // The paper's and the reference code's: 2N - 1 slots for N entities (the arm and every
  // object, static ones included: 9 on Relational Rearrange 4). The first 2N - 1 - m cycle through the
  // subgoals in the method's order from a random start; a subgoal solved when its slot comes
  // hands the slot to the next unsolved one, and the episode is over once every subgoal is
  // solved. A solved subgoal of the last phase keeps its slot, unused.
  kReference,
  // The campaign's runs to 2026-12-04: N - 1 independent uniform draws, then the m in order
  // (8 slots for SRICS on Relational Rearrange 4, whose static puck has no subgoal); a solved
  // subgoal loses its slot.
  kIndependentDraws,
};

// The attempts of one evaluation episode, chosen as they come: the first phase of the
// reference protocol depends on what the earlier attempts solved.
class AttemptSchedule {
 public:
  AttemptSchedule(const SubgoalStructure& structure, SubgoalOrder order, EvaluationProtocol protocol,
                  std::mt19937_64& rng);

  struct Slot {
    int entity = -1;
    bool skipped = false;  // solved when its slot came: no steps are taken
  };
  // The next slot, given which subgoal entities are solved now; none once the episode is over.
  std::optional<Slot> Next(const std::function<bool(int entity)>& solved);

  int slots() const { return slots_; }
  // the method's order of the subgoal entities (the last phase)
  const std::vector<int>& order() const { return ordered_; }

 private:
  EvaluationProtocol protocol_;
  std::vector<int> ordered_;
  std::vector<int> draws_;  // kIndependentDraws: the first phase
  int slots_ = 0;
  int first_phase_ = 0;
  int next_slot_ = 0;
  size_t cycle_ = 0;        // kReference: where the first phase's cycle stands
};

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
  // Compatibility: over the episode's subgoal attempts, the objects solved when an attempt
  // began that are not the attempted entity's ancestors, and how many of those it undid
  // (what the selectivity reward exists to keep at zero).
  int independent_solved = 0;
  int independent_undone = 0;
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
  uint32_t independent_solved = 0;      // summed over episodes (EpisodeMetrics)
  uint32_t independent_undone = 0;
  // independent_undone / independent_solved, -1 when no attempt began with such an object solved
  double UndoneShare() const {
    return independent_solved ? static_cast<double>(independent_undone) / independent_solved : -1.0;
  }

  // Folds one episode in; `threshold` decides per-entity success.
  void Add(const EpisodeMetrics& metrics, double threshold);
};

}  // namespace srics::rl
