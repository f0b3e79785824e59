#include <cmath>

#include "common/config/sections.h"

namespace srics::config {

void ParseAgent(YamlSection s, AgentConfig* out) {
  YamlSection net = s.Child("network");
  NetworkConfig& n = out->network;
  net.ReadInt("embed_dim", &n.embed_dim, 1, 4096);
  net.ReadInt("heads", &n.heads, 1, 64);
  if (n.embed_dim % n.heads != 0)
    net.FailRule("heads", "embed_dim (" + std::to_string(n.embed_dim) + ") must be divisible by heads (" +
                              std::to_string(n.heads) + ")");
  net.ReadIntList("policy_hidden", &n.policy_hidden, 1, 8192);
  net.ReadIntList("q_hidden", &n.q_hidden, 1, 8192);
  net.ReadDouble("log_std_min", &n.log_std_min, -100, 100);
  net.ReadDouble("log_std_max", &n.log_std_max, -100, 100);
  if (n.log_std_min >= n.log_std_max) net.FailRule("log_std_max", "must be above log_std_min");
  net.ReadDouble("initial_policy_std", &n.initial_policy_std, 0, 10);
  if (n.initial_policy_std > 0 &&
      (std::log(n.initial_policy_std) < n.log_std_min || std::log(n.initial_policy_std) > n.log_std_max))
    net.FailRule("initial_policy_std", "its log must lie in [log_std_min, log_std_max] (0: not set)");
  net.ReadDouble("hidden_bias", &n.hidden_bias, -10, 10);
  net.Finish();

  YamlSection sac = s.Child("sac");
  SacConfig& c = out->sac;
  sac.ReadDouble("discount", &c.discount, 0, 1);
  sac.ReadDouble("tau", &c.tau, 0, 1);
  sac.ReadDouble("policy_lr", &c.policy_lr, 1e-12, 1);
  sac.ReadDouble("q_lr", &c.q_lr, 1e-12, 1);
  sac.ReadDouble("alpha_lr", &c.alpha_lr, 1e-12, 1);
  sac.ReadBool("auto_entropy", &c.auto_entropy);
  sac.ReadDouble("initial_alpha", &c.initial_alpha, 0, 1e3);
  sac.ReadDouble("target_entropy", &c.target_entropy, -1e3, 1e3);
  sac.ReadDouble("reward_scale", &c.reward_scale, 1e-6, 1e6);
  sac.ReadInt("batch_size", &c.batch_size, 1, 1 << 20);
  sac.ReadDouble("grad_clip_norm", &c.grad_clip_norm, 0, 1e6);
  sac.Finish();

  YamlSection reward = s.Child("reward");
  RewardConfig& r = out->reward;
  reward.ReadEnum("selectivity_form", &r.selectivity_form,
                  {{"reference", SelectivityForm::kReference}, {"paper", SelectivityForm::kPaper}});
  reward.ReadDouble("selectivity_weight", &r.selectivity_weight, 0, 100);
  reward.ReadDouble("disturbance_weight", &r.disturbance_weight, 0, 1000);
  reward.ReadDouble("solved_threshold", &r.solved_threshold, 0, 10);
  reward.ReadDouble("epsilon", &r.epsilon, 0, 1);
  reward.Finish();

  YamlSection hac = s.Child("hac");
  HacConfig& h = out->hac;
  // a training episode has up to H * H steps: at most 10,000 (rl::kMaxEpisodeSteps)
  hac.ReadInt("horizon", &h.horizon, 1, 100);
  hac.ReadDouble("subgoal_test_probability", &h.subgoal_test_probability, 0, 1);
  hac.ReadDouble("goal_threshold", &h.goal_threshold, 1e-6, 10);
  hac.ReadInt("hindsight_goals", &h.hindsight_goals, 0, 1000);
  hac.ReadBool("bound_q", &h.bound_q);
  hac.Finish();
  s.Finish();
}

}  // namespace srics::config
