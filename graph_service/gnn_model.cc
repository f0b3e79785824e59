#include "graph_service/gnn_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace srics::graph_service {

namespace {
double PointToSegment(double px, double py, double ax, double ay, double bx, double by) {
  const double vx = bx - ax, vy = by - ay, len2 = vx * vx + vy * vy;
  const double u = len2 > 0 ? std::clamp(((px - ax) * vx + (py - ay) * vy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(ax + u * vx - px, ay + u * vy - py);
}
}  // namespace

double SegmentDistance(double p0x, double p0y, double p1x, double p1y, double q0x, double q0y, double q1x, double q1y) {
  // the sign of the cross product: which side of a line a point lies on
  auto side = [](double ox, double oy, double ax, double ay, double bx, double by) {
    const double c = (ax - ox) * (by - oy) - (ay - oy) * (bx - ox);
    return (c > 0) - (c < 0);
  };
  const int s1 = side(p0x, p0y, p1x, p1y, q0x, q0y), s2 = side(p0x, p0y, p1x, p1y, q1x, q1y);
  const int s3 = side(q0x, q0y, q1x, q1y, p0x, p0y), s4 = side(q0x, q0y, q1x, q1y, p1x, p1y);
  if (s1 * s2 < 0 && s3 * s4 < 0) return 0;  // they cross
  return std::min({PointToSegment(p0x, p0y, q0x, q0y, q1x, q1y), PointToSegment(p1x, p1y, q0x, q0y, q1x, q1y),
                   PointToSegment(q0x, q0y, p0x, p0y, p1x, p1y), PointToSegment(q1x, q1y, p0x, p0y, p1x, p1y)});
}

template <typename T>
GnnModel<T>::GnnModel(const GnnOptions& o, nn::Rng& rng)
    : options_(o),
      act_("gnn.act", o.input_dim, {o.mlp_hidden}, o.hidden_dim, rng),
      edge_send_("gnn.edge_send", o.hidden_dim + (o.edge_node_inputs ? o.input_dim : 0), 2 * o.mlp_hidden, false, rng),
      edge_recv_("gnn.edge_recv", o.hidden_dim + (o.edge_node_inputs ? o.input_dim : 0), 2 * o.mlp_hidden, true, rng),
      eff_out_("gnn.eff_out", o.mlp_hidden, o.hidden_dim, true, rng),
      pres_out_("gnn.pres_out", o.mlp_hidden, 2, true, rng),
      gru_("gnn.gru", 2 * o.hidden_dim, o.hidden_dim, rng),
      pred_("gnn.pred", o.hidden_dim, {o.mlp_hidden}, 2, rng) {
  if (o.num_entities < 2) throw std::invalid_argument("GnnModel: needs at least 2 entities");
  if (o.input_dim < 3 || o.hidden_dim < 1 || o.mlp_hidden < 1) throw std::invalid_argument("GnnModel: bad sizes");
  if (!(o.edge_prior > 0 && o.edge_prior < 1) || !(o.temperature > 0))
    throw std::invalid_argument("GnnModel: edge_prior must be in (0, 1), temperature > 0");
  if (o.edge_relative_scale > 0)
    edge_rel_ = std::make_unique<nn::Linear<T>>("gnn.edge_rel", 2, 2 * o.mlp_hidden, false, rng);
  log_prior_.resize(1, 2);
  log_prior_ << T(std::log(o.edge_prior)), T(std::log(1 - o.edge_prior));
}

template <typename T>
void GnnModel<T>::set_input_normalization(std::vector<double> mean, std::vector<double> inv_std) {
  if (mean.empty() && inv_std.empty()) {
    input_mean_.resize(0, 0);
    input_inv_std_.resize(0, 0);
    return;
  }
  if (static_cast<int>(mean.size()) != options_.input_dim || static_cast<int>(inv_std.size()) != options_.input_dim)
    throw std::invalid_argument("GnnModel: input normalization must have input_dim entries");
  input_mean_.resize(1, options_.input_dim);
  input_inv_std_.resize(1, options_.input_dim);
  for (int f = 0; f < options_.input_dim; ++f) {
    input_mean_(0, f) = T(mean[f]);
    input_inv_std_(0, f) = T(inv_std[f]);
  }
}

template <typename T>
void GnnModel<T>::BuildEdges(int batch) {
  if (edges_batch_ == batch) return;
  const int n = options_.num_entities;
  senders_.clear();
  receivers_.clear();
  senders_.reserve(static_cast<size_t>(batch) * n * (n - 1));
  receivers_.reserve(senders_.capacity());
  for (int b = 0; b < batch; ++b)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if (i == j) continue;
        senders_.push_back(b * n + i);
        receivers_.push_back(b * n + j);
      }
  edges_batch_ = batch;
}

template <typename T>
const std::vector<int>& GnnModel<T>::senders(int batch) {
  BuildEdges(batch);
  return senders_;
}

template <typename T>
const std::vector<int>& GnnModel<T>::receivers(int batch) {
  BuildEdges(batch);
  return receivers_;
}

template <typename T>
int GnnModel<T>::edge_receiver_entity(int e) const {
  const int n = options_.num_entities;
  return (e / (n - 1)) % n;
}

template <typename T>
int GnnModel<T>::edge_sender_entity(int e) const {
  const int n = options_.num_entities;
  const int j = edge_receiver_entity(e), k = e % (n - 1);
  return k < j ? k : k + 1;
}

template <typename T>
typename GnnModel<T>::Step GnnModel<T>::Forward(nn::Tape<T>& tape, nn::Var<T> h, nn::Var<T> x, int batch,
                                                const Mat& gumbel, const std::vector<int>* sender_rows) {
  BuildEdges(batch);
  const std::vector<int>& senders = sender_rows ? *sender_rows : senders_;
  const int m = options_.mlp_hidden;
  nn::Var<T> raw = x;
  if (input_mean_.size() > 0) x = tape.Mul(tape.Sub(x, tape.Constant(input_mean_)), tape.Constant(input_inv_std_));
  // first edge layer per node, then onto edges: relu(h_i W_s + h_j W_r + b)
  std::vector<nn::Var<T>> node_parts = {h};
  if (options_.edge_node_inputs) node_parts.push_back(x);
  nn::Var<T> w_send = tape.Param(edge_send_.weight());
  nn::Var<T> w_recv = tape.Param(edge_recv_.weight());
  if (edge_rel_) {
    // (xy_i - xy_j) / scale through its own slice W_rel of the first layer, also per node
    // (the layer is linear): [node, xy / scale] times [W_s; W_rel] and [W_r; -W_rel]
    node_parts.push_back(tape.MulScalar(tape.Slice(raw, 1, 0, 2), T(1.0 / options_.edge_relative_scale)));
    nn::Var<T> w_rel = tape.Param(edge_rel_->weight());
    w_send = tape.Concat({w_send, w_rel}, 0);
    w_recv = tape.Concat({w_recv, tape.MulScalar(w_rel, T(-1))}, 0);
  }
  nn::Var<T> node = node_parts.size() > 1 ? tape.Concat(node_parts, 1) : h;
  nn::Var<T> send = tape.Linear(node, w_send, {});
  nn::Var<T> recv = tape.Linear(node, w_recv, tape.Param(*edge_recv_.bias()));
  // columns [0, m) are d_eff's hidden layer, [m, 2m) d_pres's: gathered apart, each layer's
  // input and its gradient are whole matrices
  nn::Var<T> effect = eff_out_.Forward(tape, tape.GatherSumRelu(send, senders, recv, receivers_, 0, m));
  nn::Var<T> logits = pres_out_.Forward(tape, tape.GatherSumRelu(send, senders, recv, receivers_, m, m));
  // class 0 of the (straight-through) Gumbel-softmax sample is the edge
  nn::Var<T> sample = tape.GumbelSoftmax(logits, gumbel, T(options_.temperature), options_.hard);
  nn::Var<T> weight = tape.Slice(sample, 1, 0, 1);
  const Eigen::Index rows = static_cast<Eigen::Index>(batch) * options_.num_entities;
  // the messages summed per receiver, each times its edge's weight
  nn::Var<T> interaction =
      open_edges_ ? tape.ScatterAdd(effect, receivers_, rows) : tape.ScatterAdd(effect, receivers_, rows, weight);
  nn::Var<T> own = act_.Forward(tape, x);
  nn::Var<T> next = gru_.Forward(tape, tape.Concat({interaction, own}, 1), h);
  nn::Var<T> delta = pred_.Forward(tape, next);
  if (options_.delta_scale != 1) delta = tape.MulScalar(delta, T(options_.delta_scale));
  return Step{next, delta, logits, weight};
}

template <typename T>
const typename GnnModel<T>::Mat& GnnModel<T>::EdgeKlWeights(Eigen::Index rows) {
  const int n = options_.num_entities;
  if (edge_kl_weights_.size() != static_cast<size_t>(n) * n)
    throw std::invalid_argument("GnnModel: edge KL weights do not match N * N");
  if (edge_kl_rows_ != rows) {
    const Eigen::Index edges = rows * (n - 1), per_sample = static_cast<Eigen::Index>(n) * (n - 1);
    edge_kl_.resize(edges, 2);
    for (Eigen::Index e = 0; e < edges; ++e) {
      const int local = static_cast<int>(e % per_sample);
      edge_kl_.row(e).setConstant(
          T(edge_kl_weights_[static_cast<size_t>(edge_sender_entity(local)) * n + edge_receiver_entity(local)]));
    }
    edge_kl_rows_ = rows;
  }
  return edge_kl_;
}

template <typename T>
typename GnnModel<T>::Loss GnnModel<T>::WindowLoss(nn::Tape<T>& tape, const WindowBatch<T>& batch, nn::Rng& rng) {
  const int b = batch.batch, n = options_.num_entities;
  if (batch.num_entities != n) throw std::invalid_argument("WindowLoss: entity count mismatch");
  const Eigen::Index rows = static_cast<Eigen::Index>(b) * n;
  const Eigen::Index edges = rows * (n - 1);
  nn::Var<T> h = tape.Constant(Mat::Zero(rows, options_.hidden_dim));
  nn::Var<T> log_prior = tape.Constant(log_prior_);
  nn::Var<T> total{&tape, -1};
  nn::Var<T> row_weight{&tape, -1};
  if (!entity_weights_.empty()) {
    if (static_cast<int>(entity_weights_.size()) != n)
      throw std::invalid_argument("WindowLoss: entity weights do not match N");
    if (row_weights_.rows() != rows) {
      row_weights_.resize(rows, 1);
      for (Eigen::Index r = 0; r < rows; ++r) row_weights_(r, 0) = T(entity_weights_[r % n]);
    }
    row_weight = tape.Constant(row_weights_);
  }
  Loss out;
  const T onset_sq = T(options_.onset_motion * options_.onset_motion);
  for (int t = 0; t < batch.steps(); ++t) {
    const Mat noise = nn::RandomGumbel<T>(edges, 2, rng);
    Step step = Forward(tape, h, tape.Constant(batch.inputs[t]), b, noise);
    h = step.hidden;
    nn::Var<T> sq = tape.Square(tape.Sub(step.delta, tape.Constant(batch.deltas[t])));
    if (options_.onset_loss_weight > 0 && t > 0) {
      // the first step of a window has no previous step: never an onset
      Mat w = entity_weights_.empty() ? Mat::Ones(rows, 1) : row_weights_;
      const Mat& now = batch.deltas[t];
      const Mat& before = batch.deltas[t - 1];
      const Mat& x = batch.inputs[t];  // columns 0, 1: positions in metres
      for (Eigen::Index r = 0; r < rows; ++r)
        if (OnsetAtADistance(x, now, before, r, n, onset_clearance_, onset_sq))
          w(r, 0) *= T(1 + options_.onset_loss_weight);
      sq = tape.Mul(sq, tape.Constant(w));
    } else if (!entity_weights_.empty()) {
      sq = tape.Mul(sq, row_weight);
    }
    nn::Var<T> mse = tape.Mean(sq);
    // KL of the edge posterior to the Bernoulli prior, summed over edges, per receiver
    nn::Var<T> log_q = tape.LogSoftmax(step.edge_logits);
    nn::Var<T> per_edge = tape.Mul(tape.Exp(log_q), tape.Sub(log_q, log_prior));
    if (!edge_kl_weights_.empty()) per_edge = tape.Mul(per_edge, tape.Constant(EdgeKlWeights(rows)));
    nn::Var<T> kl = tape.MulScalar(tape.Sum(per_edge), T(1.0 / rows));
    nn::Var<T> term = tape.Add(mse, tape.MulScalar(kl, T(options_.kl_weight)));
    if (options_.gate_logit_decay > 0) {
      // a quadratic pull of every open gate's logit margin (> 0) towards 0, summed over
      // edges per receiver like the KL: with Adam (scale free) the margins of useful edges
      // otherwise grow without bound, dragging along edges that share their features, and
      // the KL gradient p (1 - p) (...) of a saturated gate is ~0, so it can never close.
      // Closed gates (margin < 0) are left to the KL (they settle at the prior).
      nn::Var<T> margin =
          tape.Relu(tape.Sub(tape.Slice(step.edge_logits, 1, 0, 1), tape.Slice(step.edge_logits, 1, 1, 1)));
      term = tape.Add(term, tape.MulScalar(tape.Sum(tape.Square(margin)), T(options_.gate_logit_decay / rows)));
    }
    total = total.id < 0 ? term : tape.Add(total, term);
    out.mse += static_cast<double>(mse.value()(0, 0));
    out.kl += static_cast<double>(kl.value()(0, 0));
  }
  out.total = total;
  return out;
}

template <typename T>
void GnnModel<T>::Parameters(nn::ParameterList<T>& list) {
  act_.Parameters(list);
  edge_send_.Parameters(list);
  edge_recv_.Parameters(list);
  if (edge_rel_) edge_rel_->Parameters(list);
  eff_out_.Parameters(list);
  pres_out_.Parameters(list);
  gru_.Parameters(list);
  pred_.Parameters(list);
}

template class GnnModel<float>;
template class GnnModel<double>;

}  // namespace srics::graph_service
