#pragma once
// HAC's learning side (Levy et al. 2019, two levels; docs/method.md section 3). From each
// episode an actor recorded (the full goal, the high level's subgoals, where each started and
// which were tests) it builds both levels' replay transitions with HAC's rules, keeps them in
// one transition replay per level and trains one SAC agent per level. Rewards are HAC's:
// 0 and the end of the level's episode when its goal is reached, else -1.
//
//   low level (goal: a subgoal, the xy of every entity; action: the env's):
//     hindsight action: every step of an attempt with the proposed subgoal as goal
//     hindsight goal: the attempt again for each of k goals reached in it (k - 1 random
//       states of the attempt and its last)
//   high level (goal: the full goal; action: a subgoal):
//     hindsight action: each attempt with the subgoal it reached as action (the proposed one
//       if reached, else the state reached), the episode's goal
//     hindsight goal: every attempt again for each of k goals reached in the episode (k - 1
//       random attempt ends and the last)
//     subgoal testing: a test subgoal that was missed, with the proposed subgoal as action,
//       reward -H and no bootstrap
// Episodes without subgoals (exploration) are cut into attempts of H steps with no proposal:
// they give hindsight goal transitions and the high level's hindsight action transitions.

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "common/config/agent_config.h"
#include "common/nn/serialize.h"
#include "common/rl/episode.h"
#include "common/rl/hac.h"
#include "learner/relabeler.h"
#include "learner/sac.h"

namespace srics::learner {

struct HacOptions {
  int horizon = 20;         // H: the test penalty is -H
  double threshold = 0.05;  // a goal is reached with every entity this close
  int hindsight_goals = 3;  // k per attempt (low) and per episode (high)
  rl::SubgoalBox box;       // where subgoals live (high-level actions map onto it)
  bool bound_q = true;      // both levels' Bellman targets clipped to [-H, 0]
};

// Bounds a level's Bellman targets to [-H, 0] when options.bound_q (the rewards are -1 or 0 per
// attempt step, so no return lies outside): the one rule for both levels (Learner: the low
// level's agent; HacLevels: the high level's).
void BoundHacTargets(const HacOptions& options, SacAgent* level);

// Which HAC rule made a transition.
enum class HacRule { kHindsightAction, kHindsightGoal, kSubgoalTest };

// One transition of either level, on an episode's states t0 -> t1 (low: t1 = t0 + 1; high:
// the start and end of an attempt). Goals and high-level actions hold 2N floats.
struct HacTransition {
  int t0 = 0;
  int t1 = 0;
  std::vector<float> goal;
  std::vector<float> action;
  float reward = 0;
  bool terminal = false;
  HacRule rule = HacRule::kHindsightAction;
};

struct HacTransitions {
  std::vector<HacTransition> low;
  std::vector<HacTransition> high;
};

// Both levels' transitions of one valid episode. `rng` picks the random hindsight goals.
HacTransitions BuildHacTransitions(const rl::Episode& episode, const HacOptions& options, std::mt19937_64& rng);

// Transitions of one level as fixed-size records (states padded to max_entities), oldest
// leaving first beyond the capacity; uniform sampling into SAC batches.
class TransitionReplay {
 public:
  TransitionReplay(uint64_t capacity, int max_entities, int entity_dim, int goal_dim, int action_dim);
  // Copies the transition's states from `episode` (whose layout must fit the sizes above).
  void Add(const rl::Episode& episode, const HacTransition& transition);
  // `size` uniformly drawn transitions. Precondition: size() > 0.
  void Sample(int size, std::mt19937_64& rng, TrainingBatch* batch) const;
  uint64_t size() const { return size_; }
  void Clear() { size_ = next_ = 0; }

 private:
  uint64_t capacity_;
  int max_entities_, entity_dim_, goal_dim_, action_dim_;
  size_t width_;  // floats per record
  std::vector<float> records_;
  uint64_t size_ = 0, next_ = 0;
};

// Both levels: the transition replays, the high-level agent, and updates of both. The low
// level's agent is the learner's own (it is what acts in every method).
class HacLevels {
 public:
  HacLevels(const HacOptions& options, const rl::AgentShape& low, const rl::AgentShape& high,
            const config::AgentConfig& agent, uint64_t capacity, int max_entities, uint64_t seed, int threads);

  // Builds and stores the episode's transitions (the episode is valid).
  void Add(const rl::Episode& episode);
  // Empties both replays and adds every episode again (after a checkpoint restored them).
  template <typename Episodes>
  void Rebuild(const Episodes& episodes) {
    low_replay_.Clear();
    high_replay_.Clear();
    for (const rl::Episode& e : episodes) Add(e);
  }
  // True when both levels have transitions to train on.
  bool ready() const { return low_replay_.size() > 0 && high_replay_.size() > 0; }
  // One SAC update of each level; returns the low level's statistics.
  UpdateStats Update(SacAgent& low, int batch_size);
  // The high level's statistics of the last Update (zeros before the first): learner stats
  // carry the low level's, so the node status shows these (a runaway temperature of the
  // high level froze a HAC learner once).
  const UpdateStats& last_high_update() const { return last_high_; }

  // The published weights: the high level's parameters, then the low level's.
  std::vector<float> PolicyWeights(SacAgent& low);
  std::string PolicySignature(SacAgent& low);

  // The high level's checkpoint sections (named "hac.high.*"), and loading them back.
  void AppendCheckpointSections(const LearnerCounters& counters, std::vector<nn::CheckpointSection>* sections);
  void LoadCheckpointSections(const std::vector<nn::CheckpointSection>& sections, const std::string& path);

  SacAgent& high() { return high_; }
  const TransitionReplay& low_replay() const { return low_replay_; }
  const TransitionReplay& high_replay() const { return high_replay_; }

 private:
  HacOptions options_;
  SacAgent high_;
  TransitionReplay low_replay_, high_replay_;
  std::mt19937_64 rng_;
  TrainingBatch batch_;
  UpdateStats last_high_;
};

}  // namespace srics::learner
