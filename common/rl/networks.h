#pragma once
// The goal-conditioned attention networks of SAC (docs/method.md section 3): a policy and a
// Q function, each with its own attention block over the entity set.
//
//   entity tokens (B*N x entity_dim) -> Linear(embed) -> keys, values
//   goal token [one-hot subgoal entity, goal xy, 1] -> Linear(embed, no bias) -> query
//   multi-head attention (num_heads of embed/num_heads) over valid entities -> B x embed
//   (a goal of several tokens: one query each, outputs and goal embeddings summed)
//   policy: [attention | goal embedding] -> MLP policy_hidden -> tanh-Gaussian over actions
//   Q:      [attention | goal embedding | action] -> MLP q_hidden -> 1
// Sizes come from a plain config struct (filled from YAML by the caller).

#include <string>
#include <vector>

#include "common/nn/modules.h"
#include "common/nn/tape.h"
#include "common/nn/tensor.h"

namespace srics::rl {

// Sizes of the policy and Q networks. No defaults: values come from the config file.
struct AttentionNetworkConfig {
  int entity_dim = 0;              // features per entity token
  int goal_dim = 0;                // features of one goal token
  int goal_tokens = 1;             // goal tokens per sample (2: a tied pair as one subgoal)
  int action_dim = 0;              // action size (2 for the rearrange tasks)
  int embed_dim = 0;               // token embedding (paper: 80)
  int num_heads = 0;               // heads (paper: 5 of 16)
  std::vector<int> policy_hidden;  // paper: {128, 128}
  std::vector<int> q_hidden;       // paper: {128, 128, 128}
  double log_std_min = -20;        // tanh-Gaussian log std clipping
  double log_std_max = 2;
  double initial_policy_std = 0;  // > 0: the policy's log-std output biases start at its log
  double hidden_bias = 0;         // the MLP hidden layers' biases start here (0: zero)

  // Throws std::invalid_argument naming the first bad field.
  void Validate() const;
};

// A padded batch of entity sets: entities (B*N) x entity_dim (row b*N + n), mask B x N
// (1 = real entity), goals B x (goal_tokens * goal_dim).
template <typename T>
struct EntityBatch {
  nn::Matrix<T> entities;
  nn::Matrix<T> mask;
  nn::Matrix<T> goals;
  int batch() const { return static_cast<int>(mask.rows()); }
  int max_entities() const { return static_cast<int>(mask.cols()); }
};

// Packs entity sets of different sizes (each N_i x entity_dim) and goals (B x goal_dim)
// into one padded batch; padding rows are zero with mask 0.
template <typename T>
EntityBatch<T> PackEntities(const std::vector<nn::Matrix<T>>& sets, const nn::Matrix<T>& goals);

// What the policy and the Q network share: goal-conditioned attention over the entities, then
// an MLP on [attention | goal embedding | extra inputs].
template <typename T>
class AttentionMlpNetwork {
 public:
  // Parameters in a fixed order (the flat weight layout): attention, then the MLP.
  nn::ParameterList<T> Parameters();
  const AttentionNetworkConfig& config() const { return config_; }

 protected:
  // Throws std::invalid_argument naming the first bad field of `config`.
  AttentionMlpNetwork(const std::string& name, const AttentionNetworkConfig& config, int extra_inputs,
                      const std::vector<int>& hidden, int outputs, nn::Rng& rng);

  AttentionNetworkConfig config_;
  nn::GoalAttention<T> attention_;
  nn::Mlp<T> mlp_;
};

// The SAC policy.
template <typename T>
class PolicyNetwork : public AttentionMlpNetwork<T> {
 public:
  PolicyNetwork(const std::string& name, const AttentionNetworkConfig& config, nn::Rng& rng);

  struct Output {
    nn::Var<T> action;    // B x action_dim in (-1, 1)
    nn::Var<T> log_prob;  // B x 1
  };
  // Reparameterised actions with standard normal noise eps (B x action_dim); eps = 0 gives
  // the deterministic mode. trainable = false freezes the parameters for this pass.
  Output Forward(nn::Tape<T>& tape, nn::Var<T> entities, nn::Var<T> mask, nn::Var<T> goals, const nn::Matrix<T>& eps,
                 bool trainable = true);
  // Same, from a packed batch (constants are added to the tape).
  Output Forward(nn::Tape<T>& tape, const EntityBatch<T>& batch, const nn::Matrix<T>& eps, bool trainable = true);

  // Single-observation fast path for actors: entities N x entity_dim (all real), goal
  // 1 x goal_dim. Samples (or takes the mean when deterministic) without a tape and without
  // heap allocation once N has been seen. Returns the 1 x action_dim action (valid until the
  // next call). Not thread-safe: one network per acting thread.
  const nn::Matrix<T>& Act(const Eigen::Ref<const nn::Matrix<T>>& entities, const Eigen::Ref<const nn::Matrix<T>>& goal,
                           bool deterministic, nn::Rng& rng);
  // Log-probability of the last Act's action.
  T last_log_prob() const { return last_log_prob_; }

 private:
  using AttentionMlpNetwork<T>::config_;
  using AttentionMlpNetwork<T>::attention_;
  using AttentionMlpNetwork<T>::mlp_;
  nn::TanhGaussian<T> head_;
  // inference buffers
  nn::Matrix<T> att_, goal_emb_, features_, head_out_, action_;
  std::vector<T> eps_;
  T last_log_prob_ = 0;
};

// One SAC critic Q(s, g, a).
template <typename T>
class QNetwork : public AttentionMlpNetwork<T> {
 public:
  QNetwork(const std::string& name, const AttentionNetworkConfig& config, nn::Rng& rng);

  // B x 1 Q values for actions (B x action_dim, a tape node so gradients reach the policy).
  nn::Var<T> Forward(nn::Tape<T>& tape, nn::Var<T> entities, nn::Var<T> mask, nn::Var<T> goals, nn::Var<T> actions,
                     bool trainable = true);
  nn::Var<T> Forward(nn::Tape<T>& tape, const EntityBatch<T>& batch, nn::Var<T> actions, bool trainable = true);

 private:
  using AttentionMlpNetwork<T>::attention_;
  using AttentionMlpNetwork<T>::mlp_;
};

extern template class AttentionMlpNetwork<float>;
extern template class AttentionMlpNetwork<double>;
extern template class PolicyNetwork<float>;
extern template class PolicyNetwork<double>;
extern template class QNetwork<float>;
extern template class QNetwork<double>;

}  // namespace srics::rl
