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

// How the attempts of one evaluation episode are chosen.
enum class EvaluationProtocol {
  // The reference code's (rlkit/envs/gt_wrapper.py, followed step by step, quirks included):
  // 2N - 1 slots of one attempt for N entities (the arm and every object, static ones counted:
  // 9 on Relational Rearrange 4). The method's list L of its m subgoal entities is walked
  // cyclically from a random start; the first slot takes L[start] unchecked. After each
  // attempt the walk moves on, passing over solved subgoals for free, and the episode is over
  // when it comes back to the subgoal just attempted (every other one solved, whether or not
  // that one is).
  //  - kDepth (SRICS): L in depth order. The last m slots restart the walk at L[0]; there a
  //    solved subgoal uses its slot up (skipped, no steps), and coming back to the subgoal of
  //    the last real attempt still ends the episode (in the reference too, that can leave
  //    later subgoals of the order unattempted).
  //  - kRandom (SMORL; the no-order ablation): L in entity order, one walk through all 2N - 1
  //    slots (the reference's SMORL wrapper has no ordered phase; its unordered SRICS wrapper
  //    walks the depth-ordered list, which ours does not).
  kReference,
  // The campaign's runs to 2026-12-04: N - 1 independent uniform draws, then the m in the
  // method's order (depth, or a random permutation); a solved subgoal loses its slot (8 slots
  // for SRICS on Relational Rearrange 4, whose static puck has no subgoal).
  kIndependentDraws,
};

// The attempts of one evaluation episode, chosen as they come: which subgoal a slot takes
// depends on what the earlier attempts solved.
class AttemptSchedule {
 public:
  AttemptSchedule(const SubgoalStructure& structure, SubgoalOrder order, EvaluationProtocol protocol,
                  std::mt19937_64& rng);

  struct Slot {
    int entity = -1;
    bool skipped = false;  // solved when its slot came and the slot is used up: no steps taken
  };
  // The next slot, given which subgoal entities are solved now; none once the episode is over.
  std::optional<Slot> Next(const std::function<bool(int entity)>& solved);

  int slots() const { return slots_; }
  // L: the method's list of its subgoal entities (kIndependentDraws: its last phase's order)
  const std::vector<int>& order() const { return ordered_; }

 private:
  std::optional<Slot> NextReference(const std::function<bool(int)>& solved);

  EvaluationProtocol protocol_;
  std::vector<int> ordered_;
  std::vector<int> draws_;  // kIndependentDraws: the first phase
  int slots_ = 0;
  int first_phase_ = 0;         // slots before the ordered phase (kReference + kDepth: 2N - 1 - m)
  bool ordered_phase_ = false;  // kReference: kDepth's last m slots restart at L[0]
  int next_slot_ = 0;
  size_t position_ = 0;   // kReference: where the walk stands in L
  size_t origin_ = 0;     // ... and the subgoal of the last real attempt
  bool walking_ = false;  // the last slot was skipped: the walk goes on from there
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
  double selectivity = -1;  // mean selectivity over the episode, -1 if undefined
  // Compatibility: over the episode's subgoal attempts (skipped slots not counted), the
  // objects solved when an attempt began that are not the attempted entity's ancestors, and
  // how many of those it undid
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
  double selectivity = 0;  // mean over episodes where it was defined
  int selectivity_episodes = 0;
  uint32_t independent_solved = 0;  // summed over episodes (EpisodeMetrics)
  uint32_t independent_undone = 0;
  // independent_undone / independent_solved, -1 when no attempt began with such an object solved
  double UndoneShare() const {
    return independent_solved ? static_cast<double>(independent_undone) / independent_solved : -1.0;
  }

  // Folds one episode in; `threshold` decides per-entity success.
  void Add(const EpisodeMetrics& metrics, double threshold);
  bool operator==(const EvaluationSummary&) const = default;
};

}  // namespace srics::rl
