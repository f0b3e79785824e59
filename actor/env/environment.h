#pragma once
// The environment interface seen by actors, the learner's helpers and tests. No MuJoCo here.
//
//   std::unique_ptr<Environment> env = MakeRearrangeEnv(config.env);
//   env->Reset(seed);
//   while (...) {
//     if (env->Step(action) == StepStatus::kUnstable) break;  // drop the episode
//     env->GetStates(&states);                                // N x D, row-major
//   }
//   Metrics m = env->ComputeMetrics();
//
// Entities: 0 is the arm (hand), 1..N-1 the objects present in this episode, in the order of
// their catalogue entity numbers. Each entity state is [one-hot kind (K), x, y] (+ vx, vy when
// velocities are on), in raw metres. Kind 0 is the arm, kind i the catalogue object i, so an
// object keeps its identifier in every object set (held-out combinations included).
//
// Threading: an Environment is used from one thread at a time; separate instances are
// independent and may run on separate threads.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "actor/env/types.h"

namespace srics::env {

// Layout of the entity states of the current episode (changes only at Reset), in the words of
// rl::EntityLayout (which the actor builds from it) plus each entity's kind.
struct EntityLayout {
  int num_entities = 0;     // N = 1 + objects present
  int num_kinds = 0;        // K = 1 + objects in the catalogue (one-hot width)
  bool velocities = false;  // states carry vx, vy after x, y
  int entity_dim = 0;       // D = K + 2 (+ 2 with velocities): one entity's floats
  // kind of each entity (0 = arm, i = catalogue object i); size N
  std::vector<int> kinds;
  // offset of entity i's x inside a state (y is the next one, vx, vy follow when present)
  int position_offset(int entity) const { return entity * entity_dim + num_kinds; }
};

// Distances of the current step to the episode's goals (docs/method.md section 1).
struct Metrics {
  std::vector<double> distances;   // per entity (arm first), size N
  double hand_distance = 0;        // distances[0]
  double avg_distance = 0;         // mean over all entities, arm included (paper)
  double avg_object_distance = 0;  // mean over objects only (reference code)
  bool success = false;            // sum of distances < N * success_threshold
};

// Outcome of one environment step.
enum class StepStatus {
  kOk,
  // the physics blew up (MuJoCo reset its data): the episode is over and its data must not
  // be used; Step throws until the next Reset
  kUnstable,
};

// Which object sets Reset draws from.
enum class Split { kTrain, kEval };

class Environment {
 public:
  virtual ~Environment() = default;

  // Starts an episode: draws the object set (of `split`), initial positions and goals from
  // `seed` alone. The same seed and actions give a bit-identical trajectory.
  virtual void Reset(uint64_t seed, Split split = Split::kTrain) = 0;

  // Applies one action (size action_dim(), each component clipped to [-1, 1]; non-finite
  // components throw std::invalid_argument) and advances one env step.
  virtual StepStatus Step(std::span<const double> action) = 0;

  // Number of action components (2: hand dx, dy).
  virtual int action_dim() const = 0;

  // Layout of GetStates for the current episode.
  virtual const EntityLayout& layout() const = 0;

  // Writes the N x D entity states, row-major, into *out (resized).
  virtual void GetStates(std::vector<double>* out) const = 0;

  // Entity xy positions, arm first (size N).
  virtual std::vector<Vec2> Positions() const = 0;

  // The episode's goal for each entity (arm first, size N): the hand goal is the hand's
  // start, object goals follow the spacing and connection rules.
  virtual const std::vector<Vec2>& goals() const = 0;

  // Replaces the episode's goals (size N), e.g. to evaluate a given goal.
  virtual void SetGoals(std::span<const Vec2> goals) = 0;

  // Metrics of the current step against goals().
  virtual Metrics ComputeMetrics() const = 0;

  // Env steps taken since Reset.
  virtual int steps() const = 0;

  // True once a step was unstable (until the next Reset).
  virtual bool unstable() const = 0;
};

}  // namespace srics::env
