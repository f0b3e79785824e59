#include "common/rl/networks.h"

#include <cmath>
#include <stdexcept>

namespace srics::rl {
namespace {

nn::AttentionConfig AttentionOf(const AttentionNetworkConfig& c) {
  c.Validate();
  return {c.entity_dim, c.goal_dim, c.embed_dim, c.num_heads, c.goal_tokens};
}

}  // namespace

void AttentionNetworkConfig::Validate() const {
  auto positive = [](int v, const char* field) {
    if (v <= 0) {
      throw std::invalid_argument(std::string("AttentionNetworkConfig.") + field + " must be positive, is " +
                                  std::to_string(v));
    }
  };
  positive(entity_dim, "entity_dim");
  positive(goal_dim, "goal_dim");
  positive(goal_tokens, "goal_tokens");
  positive(action_dim, "action_dim");
  positive(embed_dim, "embed_dim");
  positive(num_heads, "num_heads");
  if (embed_dim % num_heads != 0) {
    throw std::invalid_argument("AttentionNetworkConfig.num_heads " + std::to_string(num_heads) +
                                " does not divide embed_dim " + std::to_string(embed_dim));
  }
  for (int h : policy_hidden) positive(h, "policy_hidden[]");
  for (int h : q_hidden) positive(h, "q_hidden[]");
  if (!(initial_policy_std >= 0)) throw std::invalid_argument("AttentionNetworkConfig.initial_policy_std must be >= 0");
  if (!(log_std_min < log_std_max)) {
    throw std::invalid_argument("AttentionNetworkConfig.log_std_min must be < log_std_max");
  }
}

template <typename T>
EntityBatch<T> PackEntities(const std::vector<nn::Matrix<T>>& sets, const nn::Matrix<T>& goals) {
  if (sets.empty() || static_cast<Eigen::Index>(sets.size()) != goals.rows()) {
    throw std::invalid_argument("PackEntities: " + std::to_string(sets.size()) + " sets for " +
                                std::to_string(goals.rows()) + " goals");
  }
  Eigen::Index max_n = 0;
  for (const auto& s : sets) max_n = std::max(max_n, s.rows());
  const Eigen::Index dim = sets.front().cols();
  EntityBatch<T> out;
  out.entities.setZero(static_cast<Eigen::Index>(sets.size()) * max_n, dim);
  out.mask.setZero(static_cast<Eigen::Index>(sets.size()), max_n);
  out.goals = goals;
  for (size_t b = 0; b < sets.size(); ++b) {
    if (sets[b].cols() != dim) throw std::invalid_argument("PackEntities: feature sizes differ");
    out.entities.middleRows(static_cast<Eigen::Index>(b) * max_n, sets[b].rows()) = sets[b];
    out.mask.row(static_cast<Eigen::Index>(b)).head(sets[b].rows()).setOnes();
  }
  return out;
}

// ---- AttentionMlpNetwork

template <typename T>
AttentionMlpNetwork<T>::AttentionMlpNetwork(const std::string& name, const AttentionNetworkConfig& config,
                                            int extra_inputs, const std::vector<int>& hidden, int outputs, nn::Rng& rng)
    : config_(config),
      attention_(name + ".attention", AttentionOf(config), rng),
      mlp_(name + ".mlp", 2 * config.embed_dim + extra_inputs, hidden, outputs, rng) {
  if (config.hidden_bias != 0) mlp_.FillHiddenBiases(static_cast<T>(config.hidden_bias));
}

template <typename T>
nn::ParameterList<T> AttentionMlpNetwork<T>::Parameters() {
  nn::ParameterList<T> list;
  attention_.Parameters(list);
  mlp_.Parameters(list);
  return list;
}

// ---- PolicyNetwork

template <typename T>
PolicyNetwork<T>::PolicyNetwork(const std::string& name, const AttentionNetworkConfig& config, nn::Rng& rng)
    : AttentionMlpNetwork<T>(name, config, 0, config.policy_hidden, 2 * config.action_dim, rng),
      head_{static_cast<T>(config.log_std_min), static_cast<T>(config.log_std_max)},
      eps_(static_cast<size_t>(config.action_dim)) {
  // outputs [mean | log std]: the log-std half's biases start at log(initial std)
  if (config.initial_policy_std > 0)
    mlp_.output_layer()
        .bias()
        ->value.rightCols(config.action_dim)
        .setConstant(static_cast<T>(std::log(config.initial_policy_std)));
}

template <typename T>
typename PolicyNetwork<T>::Output PolicyNetwork<T>::Forward(nn::Tape<T>& tape, nn::Var<T> entities, nn::Var<T> mask,
                                                            nn::Var<T> goals, const nn::Matrix<T>& eps,
                                                            bool trainable) {
  auto att = attention_.Forward(tape, entities, mask, goals, trainable);
  nn::Var<T> features = tape.Concat({att.attention, att.goal_embedding}, 1);
  nn::Var<T> out = mlp_.Forward(tape, features, trainable);
  auto sample = head_.Forward(tape, out, eps);
  return {sample.action, sample.log_prob};
}

template <typename T>
typename PolicyNetwork<T>::Output PolicyNetwork<T>::Forward(nn::Tape<T>& tape, const EntityBatch<T>& batch,
                                                            const nn::Matrix<T>& eps, bool trainable) {
  return Forward(tape, tape.Constant(batch.entities), tape.Constant(batch.mask), tape.Constant(batch.goals), eps,
                 trainable);
}

template <typename T>
const nn::Matrix<T>& PolicyNetwork<T>::Act(const Eigen::Ref<const nn::Matrix<T>>& entities,
                                           const Eigen::Ref<const nn::Matrix<T>>& goal, bool deterministic,
                                           nn::Rng& rng) {
  const int E = config_.embed_dim, A = config_.action_dim;
  attention_.Apply(entities, goal, att_, goal_emb_);
  features_.resize(1, 2 * E);
  features_.leftCols(E) = att_;
  features_.rightCols(E) = goal_emb_;
  mlp_.Apply(features_, head_out_);
  action_.resize(1, A);
  if (!deterministic) {
    std::normal_distribution<double> normal(0.0, 1.0);
    for (int i = 0; i < A; ++i) eps_[i] = static_cast<T>(normal(rng));
  }
  last_log_prob_ = head_.Apply(head_out_.data(), A, deterministic ? nullptr : eps_.data(), action_.data());
  return action_;
}

// ---- QNetwork

template <typename T>
QNetwork<T>::QNetwork(const std::string& name, const AttentionNetworkConfig& config, nn::Rng& rng)
    : AttentionMlpNetwork<T>(name, config, config.action_dim, config.q_hidden, 1, rng) {}

template <typename T>
nn::Var<T> QNetwork<T>::Forward(nn::Tape<T>& tape, nn::Var<T> entities, nn::Var<T> mask, nn::Var<T> goals,
                                nn::Var<T> actions, bool trainable) {
  auto att = attention_.Forward(tape, entities, mask, goals, trainable);
  nn::Var<T> features = tape.Concat({att.attention, att.goal_embedding, actions}, 1);
  return mlp_.Forward(tape, features, trainable);
}

template <typename T>
nn::Var<T> QNetwork<T>::Forward(nn::Tape<T>& tape, const EntityBatch<T>& batch, nn::Var<T> actions, bool trainable) {
  return Forward(tape, tape.Constant(batch.entities), tape.Constant(batch.mask), tape.Constant(batch.goals), actions,
                 trainable);
}

template EntityBatch<float> PackEntities(const std::vector<nn::Matrix<float>>&, const nn::Matrix<float>&);
template EntityBatch<double> PackEntities(const std::vector<nn::Matrix<double>>&, const nn::Matrix<double>&);
template class AttentionMlpNetwork<float>;
template class AttentionMlpNetwork<double>;
template class PolicyNetwork<float>;
template class PolicyNetwork<double>;
template class QNetwork<float>;
template class QNetwork<double>;

}  // namespace srics::rl
