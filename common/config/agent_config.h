#pragma once
// The agent: attention networks and SAC (srics-method.md section 3). Defaults are the paper's.

#include <vector>

namespace srics::config {

// Which form of the selectivity reward (the paper's formula or the reference code's).
enum class SelectivityForm { kReference, kPaper };

struct NetworkConfig {
  int embed_dim = 80;               // entity and goal token embedding
  int heads = 5;                    // attention heads (embed_dim = heads * head_dim)
  std::vector<int> policy_hidden = {128, 128};
  std::vector<int> q_hidden = {128, 128, 128};
  double log_std_min = -20.0;
  double log_std_max = 2.0;
};

struct SacConfig {
  double discount = 0.95;
  double tau = 0.05;                // soft target update each update
  double policy_lr = 1e-3;
  double q_lr = 1e-3;
  double alpha_lr = 1e-3;
  bool auto_entropy = true;
  double initial_alpha = 1.0;
  double target_entropy = -2.0;     // -|A|
  double reward_scale = 1.0;
  int batch_size = 2048;
  double grad_clip_norm = 0.0;      // 0 = no clipping
};

struct RewardConfig {
  SelectivityForm selectivity_form = SelectivityForm::kReference;
  double selectivity_weight = 0.25;  // alpha of the paper
  double solved_threshold = 0.05;
  double epsilon = 1e-5;
};

struct AgentConfig {
  NetworkConfig network;
  SacConfig sac;
  RewardConfig reward;
};

}  // namespace srics::config
