#pragma once
// One whole episode as the algorithms see it: what actors produce, the learner stores and
// the graph service learns from. Plain data; transport converts it to and from the wire.

#include <cstdint>
#include <string>
#include <vector>

#include "common/rl/entity_layout.h"

namespace srics::rl {

// The values match the wire's EpisodeMode (idl/srics.idl); a received value outside them
// stays representable and ValidateEpisode refuses it.
enum class EpisodeMode : int32_t { kExplore = 0, kTrain = 1, kEval = 2 };

struct Episode {
  EntityLayout layout;
  std::vector<uint16_t> entity_kinds;  // N identifiers (0 = arm)
  int num_steps = 0;                   // T
  int action_dim = 2;                  // A
  std::vector<float> states;           // (T + 1) x N x D
  std::vector<float> actions;          // T x A
  int subgoal_entity = -1;             // -1: no subgoal (explore) or the full goal
  std::vector<float> goal;             // 2 (subgoal), 2N (full goal) or empty
  uint64_t ancestor_mask = 0;
  EpisodeMode mode = EpisodeMode::kExplore;
  uint32_t actor_id = 0;
  uint64_t episode_id = 0;
  uint64_t policy_version = 0;
  uint64_t graph_version = 0;
  // HAC only (empty otherwise): the high level's subgoals. Subgoal k was set at step
  // subgoal_starts[k] (the first at 0, increasing) and held until the next start or the end;
  // subgoals holds K x 2N proposed xy of every entity; subgoal_tests[k] is 1 for a test
  // subgoal (the low level acted without noise on it).
  std::vector<uint16_t> subgoal_starts;
  std::vector<float> subgoals;
  std::vector<uint8_t> subgoal_tests;

  int num_subgoals() const { return static_cast<int>(subgoal_starts.size()); }
  // steps [subgoal_start(k), subgoal_end(k)) belong to subgoal k
  int subgoal_start(int k) const { return subgoal_starts[k]; }
  int subgoal_end(int k) const { return k + 1 < num_subgoals() ? subgoal_starts[k + 1] : num_steps; }
  const float* subgoal(int k) const { return subgoals.data() + static_cast<size_t>(k) * 2 * layout.num_entities; }
  const float* state(int t) const { return states.data() + static_cast<size_t>(t) * layout.state_size(); }
  const float* action(int t) const { return actions.data() + static_cast<size_t>(t) * action_dim; }
  bool operator==(const Episode&) const = default;
};

// Bounds that hold for every run: the wire contract's (idl/srics.idl has 16-bit counts and
// 64-bit ancestor masks) and sanity bounds on values. A state 1e30 m away is finite but
// poisons the networks, so magnitudes are bounded too.
inline constexpr int kMaxEntities = 64;         // ancestor masks are 64-bit
inline constexpr int kMaxEpisodeSteps = 10000;  // T, on the wire and in memory
inline constexpr int kMaxActionDim = 64;
inline constexpr float kMaxAbsPosition = 10.0f;   // m: |x|, |y| of states and goals (the table is < 1 m)
inline constexpr float kMaxAbsVelocity = 100.0f;  // m/s: |vx|, |vy| (the hand moves at ~1 m/s)

// What a valid episode of one run looks like. The defaults accept every layout the contract
// allows (a value of 0 below means "any"); EpisodeLimitsFor (agent_shape.h) narrows them to
// the run's environment.
struct EpisodeLimits {
  int min_entities = 1;             // N, the arm plus the objects present: the environment may
  int max_entities = kMaxEntities;  // present fewer objects than its catalogue
  int num_kinds = 0;                // K, the identifier one-hot; 0: any in [1, kMaxEntities]
  bool velocities = false;          // states carry vx, vy after x, y (the wire cannot say)
  int action_dim = 0;               // A; 0: any in [1, kMaxActionDim]
  int max_steps = kMaxEpisodeSteps;
  float max_abs_position = kMaxAbsPosition;
  float max_abs_velocity = kMaxAbsVelocity;
  float max_abs_action = 1.0f;
  // HAC's subgoals: the longest a subgoal may be held (the run's H); 0: any length;
  // kNoSubgoals: this run's episodes carry none
  int max_subgoal_steps = 0;
};
inline constexpr int kNoSubgoals = -1;

// True when every value is finite and |value| <= bound: one branch-free (vectorized) pass, for
// the hot paths that check megabytes of received values; a false answer is then explained by
// the slower check that names the offender.
bool AllFiniteWithin(const float* values, size_t n, float bound);

// Limits that accept exactly one layout and action size (e.g. a data set's own).
EpisodeLimits LimitsOfLayout(const EntityLayout& layout, int action_dim);

// Empty when the episode is whole and fits `limits`: layout and sizes, entity kinds and their
// one-hot identifiers in the states, subgoal and goal, ancestor mask, mode, every value finite
// and bounded, actions in range, HAC's subgoals (train episodes only, starting at step 0,
// increasing, each held at most max_subgoal_steps, K x 2N bounded values, test flags 0 or 1). Otherwise what is wrong,
// naming the field. The learner and the graph service call it on everything that came from another process.
std::string ValidateEpisode(const Episode& episode, const EpisodeLimits& limits);

}  // namespace srics::rl
