#include "common/nn/modules.h"

#include "common/nn/attention.h"
#include "common/nn/gemm.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace srics::nn {
namespace {

template <typename T>
Var<T> Activate(Tape<T>& tape, Var<T> x, Activation act) {
  switch (act) {
    case Activation::kRelu: return tape.Relu(x);
    case Activation::kTanh: return tape.Tanh(x);
    case Activation::kNone: break;
  }
  return x;
}

template <typename T>
void ActivateInPlace(Matrix<T>& y, Activation act) {
  switch (act) {
    case Activation::kRelu: y = y.cwiseMax(T(0)); break;
    case Activation::kTanh: y = y.array().tanh().matrix(); break;
    case Activation::kNone: break;
  }
}

}  // namespace

// ---- Linear

template <typename T>
Linear<T>::Linear(std::string name, int in, int out, bool bias, Rng& rng) : in_(in), out_(out) {
  if (in <= 0 || out <= 0) throw std::invalid_argument("nn::Linear " + name + ": bad size");
  w_ = std::make_unique<Parameter<T>>(name + ".w", in, out);
  XavierUniform(w_->value, in, out, rng);
  if (bias) b_ = std::make_unique<Parameter<T>>(name + ".b", 1, out);
}

template <typename T>
Var<T> Linear<T>::Forward(Tape<T>& tape, Var<T> x, bool trainable) {
  Var<T> w = tape.Param(*w_, trainable);
  Var<T> b = b_ ? tape.Param(*b_, trainable) : Var<T>{&tape, -1};
  return tape.Linear(x, w, b);
}

template <typename T>
Var<T> Linear<T>::ForwardComposed(Tape<T>& tape, Var<T> x, Var<T> inner_w, Var<T> inner_b, bool trainable) {
  Var<T> w = WeightOn(tape, trainable);
  Var<T> b = BiasOn(tape, trainable);
  Var<T> composed_w = tape.MatMul(inner_w, w);
  Var<T> composed_b = inner_b.id >= 0 ? tape.Linear(inner_b, w, b) : b;
  return tape.Linear(x, composed_w, composed_b);
}

bool ComposingPays(long rows, long in, long mid, long out, int outers, bool inner_needed) {
  const double layered = (inner_needed ? 0.0 : double(rows) * in * mid) + double(outers) * rows * mid * out;
  const double composed = double(outers) * (double(rows) * in * out + double(in) * mid * out + double(mid) * out);
  return composed < layered;
}

template <typename T>
void Linear<T>::Apply(const Eigen::Ref<const Matrix<T>>& x, Matrix<T>& y) const {
  Gemm<T>(false, false, x, w_->value, T(0), y);
  if (b_) y.rowwise() += b_->value.row(0);
}

template <typename T>
void Linear<T>::Parameters(ParameterList<T>& list) {
  list.push_back(w_.get());
  if (b_) list.push_back(b_.get());
}

// ---- Mlp

template <typename T>
Mlp<T>::Mlp(std::string name, int in, const std::vector<int>& hidden, int out, Rng& rng, Activation hidden_act,
            Activation out_act)
    : hidden_act_(hidden_act), out_act_(out_act) {
  int prev = in;
  for (size_t i = 0; i <= hidden.size(); ++i) {
    const int next = i < hidden.size() ? hidden[i] : out;
    layers_.emplace_back(name + "." + std::to_string(i), prev, next, true, rng);
    prev = next;
  }
}

template <typename T>
void Mlp<T>::FillHiddenBiases(T value) {
  for (size_t i = 0; i + 1 < layers_.size(); ++i) layers_[i].bias()->value.setConstant(value);
}

template <typename T>
Var<T> Mlp<T>::Forward(Tape<T>& tape, Var<T> x, bool trainable) {
  for (size_t i = 0; i < layers_.size(); ++i) {
    x = layers_[i].Forward(tape, x, trainable);
    x = Activate(tape, x, i + 1 < layers_.size() ? hidden_act_ : out_act_);
  }
  return x;
}

template <typename T>
void Mlp<T>::Apply(const Eigen::Ref<const Matrix<T>>& x, Matrix<T>& y) {
  if (layers_.size() == 1) {
    layers_[0].Apply(x, y);
    ActivateInPlace(y, out_act_);
    return;
  }
  layers_[0].Apply(x, buf_[0]);
  ActivateInPlace(buf_[0], hidden_act_);
  int cur = 0;
  for (size_t i = 1; i + 1 < layers_.size(); ++i) {
    layers_[i].Apply(buf_[cur], buf_[1 - cur]);
    cur = 1 - cur;
    ActivateInPlace(buf_[cur], hidden_act_);
  }
  layers_.back().Apply(buf_[cur], y);
  ActivateInPlace(y, out_act_);
}

template <typename T>
void Mlp<T>::Parameters(ParameterList<T>& list) {
  for (Linear<T>& l : layers_) l.Parameters(list);
}

// ---- GruCell

template <typename T>
GruCell<T>::GruCell(std::string name, int in, int hidden, Rng& rng)
    : in_(in),
      hidden_(hidden),
      input_(name + ".input", in, 3 * hidden, true, rng),
      state_(name + ".state", hidden, 3 * hidden, true, rng) {}

template <typename T>
Var<T> GruCell<T>::Forward(Tape<T>& tape, Var<T> x, Var<T> h, bool trainable) {
  const int H = hidden_;
  Var<T> gi = input_.Forward(tape, x, trainable);
  Var<T> gh = state_.Forward(tape, h, trainable);
  Var<T> r = tape.Sigmoid(tape.Add(tape.Slice(gi, 1, 0, H), tape.Slice(gh, 1, 0, H)));
  Var<T> z = tape.Sigmoid(tape.Add(tape.Slice(gi, 1, H, H), tape.Slice(gh, 1, H, H)));
  Var<T> n = tape.Tanh(tape.Add(tape.Slice(gi, 1, 2 * H, H), tape.Mul(r, tape.Slice(gh, 1, 2 * H, H))));
  // h' = n + z * (h - n)
  return tape.Add(n, tape.Mul(z, tape.Sub(h, n)));
}

template <typename T>
void GruCell<T>::Parameters(ParameterList<T>& list) {
  input_.Parameters(list);
  state_.Parameters(list);
}

// ---- GoalAttention

template <typename T>
GoalAttention<T>::GoalAttention(std::string name, const AttentionConfig& c, Rng& rng)
    : config_(c),
      entity_(name + ".entity", c.entity_dim, c.embed_dim, true, rng),
      goal_(name + ".goal", c.goal_dim, c.embed_dim, false, rng),
      query_(name + ".query", c.embed_dim, c.embed_dim, true, rng),
      key_(name + ".key", c.embed_dim, c.embed_dim, true, rng),
      value_(name + ".value", c.embed_dim, c.embed_dim, true, rng),
      out_(name + ".out", c.embed_dim, c.embed_dim, true, rng) {
  if (c.num_heads <= 0 || c.embed_dim % c.num_heads != 0) {
    throw std::invalid_argument("nn::GoalAttention " + name + ": embed_dim " + std::to_string(c.embed_dim) +
                                " not divisible by " + std::to_string(c.num_heads) + " heads");
  }
  if (c.goal_tokens < 1) {
    throw std::invalid_argument("nn::GoalAttention " + name + ": goal_tokens " + std::to_string(c.goal_tokens) +
                                " must be at least 1");
  }
}

template <typename T>
typename GoalAttention<T>::Output GoalAttention<T>::Forward(Tape<T>& tape, Var<T> entities, Var<T> mask, Var<T> goals,
                                                            bool trainable) {
  // Entity tokens feed only the key and value projections, and the goal embedding's query
  // projection follows it directly: with narrow inputs (6-7 features into 80) the composed
  // weights make the training batches' largest products ~13x smaller (tests/bench/sac-update).
  const long E = config_.embed_dim;
  Var<T> k, v;
  if (ComposingPays(entities.value().rows(), entity_.in(), E, E, 2, false)) {
    Var<T> we = entity_.WeightOn(tape, trainable), be = entity_.BiasOn(tape, trainable);
    k = key_.ForwardComposed(tape, entities, we, be, trainable);
    v = value_.ForwardComposed(tape, entities, we, be, trainable);
  } else {
    Var<T> tok = entity_.Forward(tape, entities, trainable);
    k = key_.Forward(tape, tok, trainable);
    v = value_.Forward(tape, tok, trainable);
  }
  // several goal tokens: one row each (row-major, so a reshape keeps them in order)
  const int G = config_.goal_tokens;
  const Eigen::Index batch = goals.value().rows();
  Var<T> tokens = G == 1 ? goals : tape.Reshape(goals, batch * G, config_.goal_dim);
  Var<T> ge, q;
  if (ComposingPays(tokens.value().rows(), goal_.in(), E, E, 1, true)) {
    Var<T> wg = goal_.WeightOn(tape, trainable), bg = goal_.BiasOn(tape, trainable);
    ge = tape.Linear(tokens, wg, bg);
    q = query_.ForwardComposed(tape, tokens, wg, bg, trainable);
  } else {
    ge = goal_.Forward(tape, tokens, trainable);
    q = query_.Forward(tape, ge, trainable);
  }
  Var<T> heads = tape.Attention(q, k, v, mask, config_.num_heads, G);
  Var<T> attention = out_.Forward(tape, heads, trainable);
  if (G == 1) return {attention, ge};
  // sum over each sample's real tokens: the token's last feature is 1 for a real one, 0 for padding
  // (local: the learner's shard threads run Forward on one network at once)
  std::vector<int> sample_of_token(static_cast<size_t>(batch * G));
  for (size_t r = 0; r < sample_of_token.size(); ++r) sample_of_token[r] = static_cast<int>(r / G);
  Var<T> real = tape.Constant(tokens.value().rightCols(1));
  return {tape.ScatterAdd(attention, sample_of_token, batch, real), tape.ScatterAdd(ge, sample_of_token, batch, real)};
}

template <typename T>
void GoalAttention<T>::Apply(const Eigen::Ref<const Matrix<T>>& entities, const Eigen::Ref<const Matrix<T>>& goal,
                             Matrix<T>& attention, Matrix<T>& goal_embedding) {
  entity_.Apply(entities, tok_);
  key_.Apply(tok_, k_);
  value_.Apply(tok_, v_);
  const int G = config_.goal_tokens, D = config_.goal_dim;
  if (G == 1) {
    goal_.Apply(goal, goal_embedding);
    ApplyQuery(goal_embedding, attention);
    return;
  }
  attention.setZero(1, config_.embed_dim);
  goal_embedding.setZero(1, config_.embed_dim);
  for (int j = 0; j < G; ++j) {
    const auto token = goal.middleCols(static_cast<Eigen::Index>(j) * D, D);
    if (token(0, D - 1) == T(0)) continue;  // padding
    goal_.Apply(token, token_embedding_);
    ApplyQuery(token_embedding_, token_attention_);
    goal_embedding += token_embedding_;
    attention += token_attention_;
  }
}

template <typename T>
void GoalAttention<T>::ApplyQuery(const Eigen::Ref<const Matrix<T>>& goal_embedding, Matrix<T>& attention) {
  const Eigen::Index ents = k_.rows(), E = config_.embed_dim;
  query_.Apply(goal_embedding, q_);
  heads_.resize(1, E);
  w_.resize(1, config_.num_heads * ents);
  // the same math as the tape's Attention op (common/nn/attention.h), every entity present
  attention::Forward(attention::Sample<T>{q_.data(), k_.data(), v_.data(), E, nullptr, ents}, E,
                     static_cast<int64_t>(config_.num_heads), w_.data(), heads_.data());
  out_.Apply(heads_, attention);
}

template <typename T>
void GoalAttention<T>::Parameters(ParameterList<T>& list) {
  entity_.Parameters(list);
  goal_.Parameters(list);
  query_.Parameters(list);
  key_.Parameters(list);
  value_.Parameters(list);
  out_.Parameters(list);
}

// ---- TanhGaussian

template <typename T>
typename TanhGaussian<T>::Sample TanhGaussian<T>::Forward(Tape<T>& tape, Var<T> mean_log_std,
                                                          const Matrix<T>& eps) const {
  const Eigen::Index A = mean_log_std.cols() / 2;
  if (eps.rows() != mean_log_std.rows() || eps.cols() != A) {
    throw std::invalid_argument("nn::TanhGaussian: noise shape does not match the head");
  }
  Var<T> mean = tape.Slice(mean_log_std, 1, 0, A);
  Var<T> log_std = tape.Clamp(tape.Slice(mean_log_std, 1, A, A), log_std_min, log_std_max);
  Var<T> u = tape.Add(mean, tape.Mul(tape.Exp(log_std), tape.Constant(eps)));
  Var<T> action = tape.Tanh(u);
  // gaussian density of u: -eps^2/2 - log std - log(2 pi)/2 (eps is constant here)
  const T half_log_2pi = T(0.5) * std::log(T(2) * T(M_PI));
  Var<T> base = tape.Constant((T(-0.5) * eps.array().square() - half_log_2pi).matrix());
  // tanh correction, stable form: log(1 - tanh(u)^2) = -2 (u + softplus(-2u) - log 2)
  Var<T> corr =
      tape.MulScalar(tape.AddScalar(tape.Add(u, tape.Softplus(tape.MulScalar(u, T(-2)))), -std::log(T(2))), T(-2));
  Var<T> log_prob = tape.Sum(tape.Sub(tape.Sub(base, log_std), corr), 1);
  return {action, log_prob};
}

template <typename T>
T TanhGaussian<T>::Apply(const T* mean_log_std, int action_dim, const T* eps, T* action) const {
  const T half_log_2pi = T(0.5) * std::log(T(2) * T(M_PI));
  T log_prob = 0;
  for (int i = 0; i < action_dim; ++i) {
    const T log_std = std::clamp(mean_log_std[action_dim + i], log_std_min, log_std_max);
    const T e = eps ? eps[i] : T(0);
    const T u = mean_log_std[i] + std::exp(log_std) * e;
    action[i] = std::tanh(u);
    const T softplus = std::max(T(-2) * u, T(0)) + std::log1p(std::exp(-std::abs(T(2) * u)));
    log_prob += T(-0.5) * e * e - half_log_2pi - log_std + T(2) * (u + softplus - std::log(T(2)));
  }
  return log_prob;
}

template class Linear<float>;
template class Linear<double>;
template class Mlp<float>;
template class Mlp<double>;
template class GruCell<float>;
template class GruCell<double>;
template class GoalAttention<float>;
template class GoalAttention<double>;
template struct TanhGaussian<float>;
template struct TanhGaussian<double>;

}  // namespace srics::nn
