#pragma once
// Builds SAC training batches from the replay: samples transitions, relabels their goals
// (original / future state of the same entity / sampled from the goal distribution) and
// recomputes the method's reward for the new goal (docs/method.md section 3).

#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "common/config/agent_config.h"
#include "common/config/learner_config.h"
#include "common/config/run_config.h"
#include "common/rl/graph.h"
#include "learner/replay_buffer.h"

namespace srics::learner {

// The region goals are drawn from (subgoal goals: x [-0.2, 0.2], y [0.45, 0.7]).
struct GoalRegion {
  double x_min = -0.2, x_max = 0.2, y_min = 0.45, y_max = 0.7;
};

// A batch in the layout the attention networks take. Entities are padded to max_entities;
// padded rows are zero and masked out.
struct TrainingBatch {
  int size = 0;                      // B
  int max_entities = 0;              // N
  int entity_dim = 0;                // D
  int goal_dim = 0;                  // G: [kind one-hot (K), goal xy, 1] per goal token for subgoals; 2N for full goals
  int action_dim = 0;                // A
  std::vector<float> entities;       // (B*N) x D, state t
  std::vector<float> next_entities;  // (B*N) x D, state t + 1
  std::vector<float> mask;           // B x N, 1 = real entity
  std::vector<float> goal;           // B x G
  std::vector<float> action;         // B x A
  std::vector<float> reward;         // B
  std::vector<int> subgoal_entity;   // B (-1 for full goals; a pair's first entity)
  // B: 1 where the transition ends its level's episode (HAC: goal reached, missed test
  // subgoal), so its target does not bootstrap; empty: every transition bootstraps
  std::vector<float> terminal;
};

// Which goal each sample ended up with, for statistics and tests.
enum class GoalSource { kOriginal, kFuture, kSampled };

class Relabeler {
 public:
  // goal_tokens: the networks' goal tokens per sample; 2 (graph.object_ties: joint) pairs the
  // graph's mutual ancestors into one subgoal (rl::PairMutualAncestors).
  Relabeler(config::Method method, const config::RewardConfig& reward, const config::RelabelConfig& relabel,
            GoalRegion region, uint64_t seed, int goal_tokens = 1);

  // The ancestor sets used for rewards and for picking subgoals of episodes that have none
  // (explore episodes). Until called, every entity is a subgoal with no ancestors.
  // (A fixed structure, indexed by the episode's entities: for episodes of every entity.)
  void SetSubgoalStructure(const rl::SubgoalStructure& structure);
  // The run's catalogue graph: each episode's ancestor sets follow from it and the episode's
  // entity_kinds (rl::EpisodeSubgoalStructure), so a subset of the objects is indexed right.
  void SetGraph(const rl::InteractionGraph& catalogue);

  // Fills *batch with `size` relabeled transitions. Precondition: !replay.empty().
  void Sample(const ReplayBuffer& replay, int size, TrainingBatch* batch, std::vector<GoalSource>* sources = nullptr);

  bool full_goal() const { return method_ == config::Method::kSacHer; }

  // The object attempted together with the episode's subgoal entity (a tied pair, goal_tokens
  // 2), as this episode's structure pairs them; -1 for none.
  int PartnerOf(const rl::Episode& episode);

  // The random stream of sampling and relabeling, for checkpoints (a resumed learner draws
  // the batches the uninterrupted one would have).
  std::mt19937_64& rng() { return rng_; }

 private:
  // the structure of this episode's entities (the fixed one, or the graph's mapped; cached)
  const rl::SubgoalStructure* StructureOf(const rl::Episode& episode);
  int PickSubgoalEntity(const rl::Episode& episode);
  double Reward(const rl::Episode& episode, const rl::SubgoalStructure* structure, int t,
                const rl::SubgoalUnit& subgoal, const float* goal) const;

  config::Method method_;
  config::RewardConfig reward_;
  config::RelabelConfig relabel_;
  GoalRegion region_;
  std::mt19937_64 rng_;
  int goal_tokens_;
  rl::SubgoalStructure structure_;
  bool have_structure_ = false;
  rl::CatalogueSubgoals catalogue_;
  // per combination of present entities (a handful per run): its structure
  std::map<std::vector<uint16_t>, rl::SubgoalStructure> by_kinds_;
};

}  // namespace srics::learner
