#pragma once
// The agent: attention networks and SAC (docs/method.md section 3). Defaults are the paper's.

#include <vector>

namespace srics::config {

// Which form of the selectivity reward (the paper's formula or the reference code's).
enum class SelectivityForm { kReference, kPaper };

struct NetworkConfig {
  int embed_dim = 80;  // entity and goal token embedding
  int heads = 5;       // attention heads (embed_dim = heads * head_dim)
  std::vector<int> policy_hidden = {128, 128};
  std::vector<int> q_hidden = {128, 128, 128};
  double log_std_min = -20.0;
  double log_std_max = 2.0;
  // Starting values (the reference code's, reference-deviations row 9; 0 = Xavier weights with
  // zero biases everywhere): the policy's log-std outputs start at log(initial_policy_std) (its
  // std about 0.2 instead of about 1), every MLP hidden layer's bias at hidden_bias (0.1).
  double initial_policy_std = 0.0;
  double hidden_bias = 0.0;
};

struct SacConfig {
  double discount = 0.95;
  double tau = 0.05;  // soft target update each update
  double policy_lr = 1e-3;
  double q_lr = 1e-3;
  double alpha_lr = 1e-3;
  bool auto_entropy = true;
  double initial_alpha = 1.0;
  double target_entropy = -2.0;  // -|A|
  double reward_scale = 1.0;
  int batch_size = 2048;
  double grad_clip_norm = 0.0;  // 0 = no clipping
};

struct RewardConfig {
  // the paper's since 2026-12-03: the campaign's ablation on Relational Rearrange 4 (3 seeds,
  // docs/results.md) ended at 0.74 ± 0.05 of the passive object distance with it against 0.81 ±
  // 0.04 with the reference code's form (kReference)
  SelectivityForm selectivity_form = SelectivityForm::kPaper;
  double selectivity_weight = 0.25;  // alpha of the paper
  // Not in the paper (issue 34's experiment): minus this times the summed motion (m per step)
  // of the entities that are neither the subgoal entity nor its ancestors, on every step.
  // Both forms' selectivity term is blind to motion of others while the subgoal entity does
  // not move (a hand crossing solved pucks on its way costs nothing); this term is not. 0 = off
  double disturbance_weight = 0;
  double solved_threshold = 0.05;
  double epsilon = 1e-5;
};

// The HAC baseline (Levy et al. 2019) with 2 levels: the high level proposes a subgoal (the xy
// of every entity) every `horizon` steps or when the low level reaches it; a training episode
// is `horizon` high-level actions. Rewards are HAC's: 0 when the level's goal is reached
// (every entity within goal_threshold), else -1; a missed test subgoal costs -horizon.
struct HacConfig {
  int horizon = 20;                       // H: low steps per subgoal, subgoals per episode
  double subgoal_test_probability = 0.3;  // the low level acts without noise on a test subgoal
  double goal_threshold = 0.05;           // m, per entity (Euclidean xy distance)
  int hindsight_goals = 3;                // goal replay: per attempt, k-1 random achieved states + the last
  // HAC bounds every level's Q to [-horizon, 0] (Levy et al.'s critics end in a negative
  // sigmoid); here each level's Bellman targets are clipped to that range. Without it a run's
  // high level diverged until every update was non-finite (docs/results.md, HAC)
  bool bound_q = true;
};

struct AgentConfig {
  NetworkConfig network;
  SacConfig sac;
  RewardConfig reward;
  HacConfig hac;
};

}  // namespace srics::config
