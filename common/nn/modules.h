#pragma once
// Layers built on the tape: Linear, MLP, GRU cell, goal-conditioned multi-head attention and
// the tanh-Gaussian policy head. Each module owns its parameters (stable addresses), lists
// them in a fixed order with Parameters(), runs on a tape with Forward(), and offers an
// Apply() inference path that writes into caller-owned buffers without a tape.

#include <memory>
#include <string>
#include <vector>

#include "common/nn/tape.h"
#include "common/nn/tensor.h"

namespace srics::nn {

// Activation applied after a layer.
enum class Activation { kNone, kRelu, kTanh };

// y = x W + b with W (in x out), Xavier-uniform init and zero bias.
template <typename T>
class Linear {
 public:
  // name prefixes the parameter names ("<name>.w", "<name>.b").
  Linear(std::string name, int in, int out, bool bias, Rng& rng);

  // Records y = x W (+ b) on the tape; x is batch x in.
  Var<T> Forward(Tape<T>& tape, Var<T> x, bool trainable = true);
  // Records y = inner(x) W (+ b) for a layer `inner` with nothing between the two, as one
  // product with the composed weight: x (Wi W) + (bi W + b), given inner's weight and bias as
  // recorded on the tape (bias id < 0: none). The same function up to float rounding; fewer
  // multiply-adds when inner's input is narrow (ComposingPays).
  Var<T> ForwardComposed(Tape<T>& tape, Var<T> x, Var<T> inner_w, Var<T> inner_b, bool trainable = true);
  // This layer's weight and bias as tape variables (the bias's id is < 0 without one).
  Var<T> WeightOn(Tape<T>& tape, bool trainable) { return tape.Param(*w_, trainable); }
  Var<T> BiasOn(Tape<T>& tape, bool trainable) { return b_ ? tape.Param(*b_, trainable) : Var<T>{&tape, -1}; }
  // Computes y = x W (+ b) into y (resized only if its shape differs) without a tape.
  void Apply(const Eigen::Ref<const Matrix<T>>& x, Matrix<T>& y) const;

  int in() const { return in_; }
  int out() const { return out_; }
  Parameter<T>& weight() { return *w_; }
  Parameter<T>* bias() { return b_.get(); }  // null when built without bias
  // Appends this layer's parameters to list.
  void Parameters(ParameterList<T>& list);

 private:
  int in_, out_;
  std::unique_ptr<Parameter<T>> w_, b_;
};

// Whether `outers` layers (mid -> out each) applied to one layer's output (in -> mid, over
// `rows` rows) take fewer multiply-adds as composed products (ForwardComposed) than layer by
// layer. inner_needed: the inner layer's output is computed anyway, so composing saves only the
// outer products.
bool ComposingPays(long rows, long in, long mid, long out, int outers, bool inner_needed);

// A stack of Linear layers with an activation between them: in -> hidden... -> out.
template <typename T>
class Mlp {
 public:
  // hidden activations are `hidden_act`; the last layer is followed by `out_act`.
  Mlp(std::string name, int in, const std::vector<int>& hidden, int out, Rng& rng,
      Activation hidden_act = Activation::kRelu, Activation out_act = Activation::kNone);

  Var<T> Forward(Tape<T>& tape, Var<T> x, bool trainable = true);
  // Inference into y; ping-pong buffers are kept inside, so Apply is not thread-safe and
  // does not allocate once the batch size has been seen.
  void Apply(const Eigen::Ref<const Matrix<T>>& x, Matrix<T>& y);

  int in() const { return layers_.front().in(); }
  int out() const { return layers_.back().out(); }
  void Parameters(ParameterList<T>& list);
  // Sets the bias of every layer but the last to `value` (a starting value; rng untouched).
  void FillHiddenBiases(T value);
  Linear<T>& output_layer() { return layers_.back(); }

 private:
  std::vector<Linear<T>> layers_;
  Activation hidden_act_, out_act_;
  Matrix<T> buf_[2];
};

// A GRU cell (PyTorch convention): r = s(x Wir + h Whr + b), z = s(x Wiz + h Whz + b),
// n = tanh(x Win + bin + r * (h Whn + bhn)), h' = (1 - z) * n + z * h.
template <typename T>
class GruCell {
 public:
  GruCell(std::string name, int in, int hidden, Rng& rng);

  // One step: x is batch x in, h is batch x hidden; returns the new hidden state.
  Var<T> Forward(Tape<T>& tape, Var<T> x, Var<T> h, bool trainable = true);

  int hidden() const { return hidden_; }
  void Parameters(ParameterList<T>& list);

 private:
  int in_, hidden_;
  Linear<T> input_, state_;  // fused gates: columns [r | z | n]
};

// Sizes of the goal-conditioned attention block.
struct AttentionConfig {
  int entity_dim;  // features per entity token
  int goal_dim;    // features of the goal token
  int embed_dim;   // token embedding size (paper: 80)
  int num_heads;   // heads (paper: 5, of 16 each); must divide embed_dim
  // goal tokens per sample: a goal of several entities (a tied pair attempted as one) is one
  // token each, side by side; a token whose last feature (the constant 1) is 0 is padding
  int goal_tokens = 1;
};

// The goal-conditioned multi-head attention block: entity tokens -> Linear(embed) -> keys and
// values; goal token -> Linear(embed, no bias) = goal embedding -> query; multi-head
// attention over the valid entities of each sample, then an output projection. Permutation
// invariant in the entities, and padded entities (mask 0) have no influence. With several goal
// tokens each runs its own query, and the attention outputs and goal embeddings of the real
// tokens are summed (one token: the same parameters and the same values as one query).
template <typename T>
class GoalAttention {
 public:
  GoalAttention(std::string name, const AttentionConfig& config, Rng& rng);

  struct Output {
    Var<T> attention;       // B x embed
    Var<T> goal_embedding;  // B x embed
  };
  // entities: (B*N) x entity_dim, row b*N + n; mask: B x N (1 = real entity) or id < 0;
  // goals: B x (goal_tokens * goal_dim).
  Output Forward(Tape<T>& tape, Var<T> entities, Var<T> mask, Var<T> goals, bool trainable = true);

  // Single-sample inference: entities N x entity_dim (all valid), goal 1 x (goal_tokens *
  // goal_dim); writes
  // the attention output and goal embedding (1 x embed each) without a tape or allocation
  // once N has been seen.
  void Apply(const Eigen::Ref<const Matrix<T>>& entities, const Eigen::Ref<const Matrix<T>>& goal, Matrix<T>& attention,
             Matrix<T>& goal_embedding);

  const AttentionConfig& config() const { return config_; }
  void Parameters(ParameterList<T>& list);

 private:
  // one query's attention output (1 x embed) from the keys and values in k_, v_
  void ApplyQuery(const Eigen::Ref<const Matrix<T>>& goal_embedding, Matrix<T>& attention);

  AttentionConfig config_;
  Linear<T> entity_, goal_, query_, key_, value_, out_;
  Matrix<T> tok_, k_, v_, q_, heads_, w_, token_embedding_, token_attention_;
};

// The tanh-squashed diagonal Gaussian of SAC. The network outputs [mean | raw log std]
// (batch x 2A); log std is clamped to [log_std_min, log_std_max].
template <typename T>
struct TanhGaussian {
  T log_std_min = -20;
  T log_std_max = 2;

  struct Sample {
    Var<T> action;    // B x A, tanh(mean + std * eps)
    Var<T> log_prob;  // B x 1, exact log density of the squashed action
  };
  // Reparameterised sample with the given standard normal noise eps (B x A); eps = 0 gives
  // the deterministic mode tanh(mean) and its density.
  Sample Forward(Tape<T>& tape, Var<T> mean_log_std, const Matrix<T>& eps) const;

  // Tape-free single sample from one row [mean | raw log std]; eps may be null (mode).
  // Writes the action (length A) and returns the log-probability.
  T Apply(const T* mean_log_std, int action_dim, const T* eps, T* action) const;
};

extern template class Linear<float>;
extern template class Linear<double>;
extern template class Mlp<float>;
extern template class Mlp<double>;
extern template class GruCell<float>;
extern template class GruCell<double>;
extern template class GoalAttention<float>;
extern template class GoalAttention<double>;
extern template struct TanhGaussian<float>;
extern template struct TanhGaussian<double>;

}  // namespace srics::nn
