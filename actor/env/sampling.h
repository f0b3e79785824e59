#pragma once
// Initial positions, evaluation goals and subgoal goals as pure functions of a config and a
// random generator (docs/method.md section 1). The environment uses them at Reset; the
// learner may use SampleSubgoal for relabeling.
//
// Spacing rules: object-object distances >= the configured minimum plus, for objects larger
// than sampling.reference_radius, the excess of each bounding radius; object-hand likewise.
// Connected objects: the second is placed from the first (initially within the link length;
// goals exactly at length * (sin phi, cos phi), one phi per draw as in the reference).

#include <span>
#include <stdexcept>
#include <vector>

#include "actor/env/types.h"
#include "common/config/env_config.h"

namespace srics::env {

// Thrown when rejection sampling finds no placement within sampling.max_attempts.
class SamplingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Draws the entity numbers present in one episode: uniformly one of `object_sets` (or of
// `eval_object_sets` when eval and that list is not empty); all objects when no set is given.
// Sorted ascending.
std::vector<int> SampleObjectSet(const config::EnvConfig& config, bool eval, Rng& rng);

// Minimum distance between two objects of bounding radii ra, rb for a base spacing.
double RequiredDistance(const config::SamplingConfig& sampling, double base, double ra, double rb);

// Axis-aligned box [lo, hi] that keeps an object of bounding radius r inside `low..high` and
// off the walls.
void ObjectBox(const config::EnvConfig& config, const std::vector<double>& low, const std::vector<double>& high,
               double r, Vec2* lo, Vec2* hi);

// Initial xy of the objects `present` (entity numbers), in that order. Throws SamplingError.
std::vector<Vec2> SampleInitialPositions(const config::EnvConfig& config, std::span<const int> present, Rng& rng);

// Evaluation goals, arm first: the hand goal is hand.start, then one goal per present object
// (same order as `present`). `initial` are the objects' initial xy (used for static objects
// when sampling.static_object_random_goal is false). Throws SamplingError.
std::vector<Vec2> SampleGoals(const config::EnvConfig& config, std::span<const int> present,
                              std::span<const Vec2> initial, Rng& rng);

// A goal for a subgoal of any entity: uniform in sampling.subgoal_low..subgoal_high.
Vec2 SampleSubgoal(const config::SamplingConfig& sampling, Rng& rng);

}  // namespace srics::env
