#pragma once
// The recurrent GNN dynamics model of SRICS (docs/method.md section 2). For every entity j
// at step t, with hidden states h(t) and node input x_j = [x, y, kind one-hot, action]:
//   w_ij      = [softmax(d_pres([h_i, h_j]))]_0 sampled by (straight-through) Gumbel-softmax
//   h_int_j   = sum_{i != j} w_ij d_eff([h_i, h_j])
// (with edge_node_inputs the edge MLPs see [h_i, x_i, h_j, x_j]: the current positions and
// action reach the interaction without the one-step lag of the hidden states)
//   h_act_j   = d_act(x_j)
//   h_j(t+1)  = GRU([h_int_j, h_act_j], h_j(t))
//   Δxy_j     = delta_scale * d_pred(h_j(t+1))
// With edge_relative_scale > 0 the first edge layer also gets (xy_i - xy_j) / scale (contact
// and rope effects depend on where the entities are relative to each other).
// w_ij is "entity i acts on entity j". The first layer of d_eff and d_pres on [h_i, h_j] is
// computed per node (h_i W_s + h_j W_r, the same linear map; the relative position's part
// likewise, as xy_i W / scale - xy_j W / scale) before gathering onto edges, so the per-edge
// work is one pass for the sum and relu (Tape::GatherSumRelu, d_eff's and d_pres's columns
// apart) and the two output layers.
// The reference's batch norm in the MLPs is left out (its inputs are GRU states in [-1, 1]).

#include <memory>
#include <vector>

#include "common/nn/modules.h"
#include "common/nn/tape.h"
#include "graph_service/dataset.h"

namespace srics::graph_service {

// Distance between the segments p0-p1 and q0-q1 in the plane (0 where they cross).
double SegmentDistance(double p0x, double p0y, double p1x, double p1y, double q0x, double q0y, double q1x, double q1y);

// Whether rows a and b of one step stay farther apart than `distance` (metres) throughout the
// step, each moving along a straight line: x's columns 0, 1 are positions, dx's the step's
// motion. Not only before and after: the hand moves up to ~10 cm in a step and can hit an
// object it is clear of at both ends (it ends where the object was; the object has flown).
template <class Matrix>
bool ApartThroughTheStep(const Matrix& x, const Matrix& dx, Eigen::Index a, Eigen::Index b, double distance) {
  auto at = [&](Eigen::Index r, int k) { return static_cast<double>(x(r, k)); };
  auto to = [&](Eigen::Index r, int k) { return at(r, k) + static_cast<double>(dx(r, k)); };
  return SegmentDistance(at(a, 0), at(a, 1), to(a, 0), to(a, 1), at(b, 0), at(b, 1), to(b, 0), to(b, 1)) > distance;
}

// Whether row r (entity r % n of its sample of n entities) starts moving at this step, with
// nothing in reach: |Δxy| > onset_motion now (onset_sq = onset_motion^2) and not in the step
// before, and every other entity i of the sample farther from it than clearance[i * n + j]
// along the step (ApartThroughTheStep; a clearance of 0, or a clearance not of n * n: no
// condition). x's columns 0, 1 are positions, `now` and `before` the steps' motions. The onsets
// the loss weights (GnnModel::WindowLoss), and a tie's evidence (GnnTrainer::onsets_at_a_distance).
template <class Matrix>
bool OnsetAtADistance(const Matrix& x, const Matrix& now, const Matrix& before, Eigen::Index r, int n,
                      const std::vector<double>& clearance, typename Matrix::Scalar onset_sq) {
  if (!(now.row(r).squaredNorm() > onset_sq && before.row(r).squaredNorm() <= onset_sq)) return false;
  if (clearance.size() != static_cast<size_t>(n) * n) return true;
  const int j = static_cast<int>(r % n);
  for (int i = 0; i < n; ++i) {
    const double c = clearance[static_cast<size_t>(i) * n + j];
    if (i != j && c > 0 && !ApartThroughTheStep(x, now, r - j + i, r, c)) return false;
  }
  return true;
}

// Sizes and loss settings of the model.
struct GnnOptions {
  int num_entities = 0;           // N
  int input_dim = 0;              // F = 2 + K + A
  int hidden_dim = 20;            // per-entity recurrent state
  int mlp_hidden = 100;           // hidden width of every d_* MLP
  bool edge_node_inputs = false;  // edge MLPs also see x_i, x_j (not in the reference)
  // > 0: the edge MLPs also see the relative position (xy_i - xy_j) / edge_relative_scale of
  // the raw (unstandardised) inputs (not in the recurrent reference model)
  double edge_relative_scale = 0;
  double delta_scale = 1;    // Δxy = delta_scale * d_pred(h): output units in metres
  double edge_prior = 0.05;  // Bernoulli prior of an edge (KL target)
  double kl_weight = 1e-5;
  double temperature = 0.5;  // Gumbel-softmax temperature
  bool hard = true;          // straight-through hard samples (the reference); false = soft
  // > 0: loss += gate_logit_decay * sum over edges of max(0, logit_0 - logit_1)^2 / (N * B)
  double gate_logit_decay = 0;
  // > 0: an entity's squared error at a step where it starts moving (|Δxy| > onset_motion
  // now, not in the previous step of the window) is weighted 1 + onset_loss_weight
  double onset_loss_weight = 0;
  double onset_motion = 1e-3;
};

// The model; T is float for training and double for gradient checks.
template <typename T>
class GnnModel {
 public:
  using Mat = nn::Matrix<T>;

  GnnModel(const GnnOptions& options, nn::Rng& rng);

  // One step of the recurrence for `batch` samples on a tape.
  struct Step {
    nn::Var<T> hidden;       // (B*N) x H, h(t+1)
    nn::Var<T> delta;        // (B*N) x 2, predicted xy change
    nn::Var<T> edge_logits;  // E x 2, E = B*N*(N-1), edge order of receivers()/senders()
    nn::Var<T> edge_weight;  // E x 1, the (sampled) weight used
  };
  // h: (B*N) x H, x: (B*N) x F; gumbel: E x 2 standard Gumbel noise (all zero: the
  // deterministic argmax / softmax of the logits). sender_rows (size E, optional) replaces
  // the row each edge takes its sender's features from (default: senders(batch)): the cut
  // read-out points an edge at the same entity of another sample, which keeps the message's
  // distribution but removes what it says about this sample's sender.
  Step Forward(nn::Tape<T>& tape, nn::Var<T> h, nn::Var<T> x, int batch, const Mat& gumbel,
               const std::vector<int>* sender_rows = nullptr);

  // Loss of a window batch with teacher forcing (inputs are the true states), summed over
  // the window's transitions as in the reference: sum_t [MSE_t + kl_weight * KL_t], where
  // MSE_t is the mean squared error of the position change over all entities and axes and
  // KL_t = sum over edges of KL(q_ij || prior) / (N * B). Gumbel noise is drawn from rng.
  struct Loss {
    nn::Var<T> total;
    double mse = 0;  // sum over steps of MSE_t
    double kl = 0;   // sum over steps of KL_t
  };
  Loss WindowLoss(nn::Tape<T>& tape, const WindowBatch<T>& batch, nn::Rng& rng);

  // Edges of a batch of `batch` samples: edge e goes from senders()[e] to receivers()[e]
  // (rows b*N + n); for receiver row r the N-1 edges are e = r*(N-1) + k, senders in
  // increasing entity order skipping the receiver.
  const std::vector<int>& senders(int batch);
  const std::vector<int>& receivers(int batch);
  // Entity index (within its sample) of edge e's sender and receiver.
  int edge_sender_entity(int e) const;
  int edge_receiver_entity(int e) const;

  const GnnOptions& options() const { return options_; }
  // Per-entity weights of the squared error (size N; empty = all 1).
  void set_entity_loss_weights(std::vector<double> w) { entity_weights_ = std::move(w); }
  // with onset_loss_weight: an onset of j is weighted only when every entity i is farther from
  // j than clearance[i * N + j] along the step's straight paths (ApartThroughTheStep; 0: no
  // condition; infinity: j's onsets never count; empty: every onset counts)
  void set_onset_clearance(std::vector<double> c) { onset_clearance_ = std::move(c); }
  void set_onset_loss_weight(double w) { options_.onset_loss_weight = w; }
  // Per-edge factors of the KL term, w[i * N + j] for the edge i -> j (size N * N; empty: every
  // edge 1, the plain KL).
  void set_edge_kl_weights(std::vector<double> w) {
    edge_kl_weights_ = std::move(w);
    edge_kl_rows_ = 0;  // rebuilt for the next batch
  }
  // Changes the weight of the KL term (annealing).
  void set_kl_weight(double w) { options_.kl_weight = w; }
  // Standardisation of the node inputs: every network sees (x - mean) * inv_std (size F
  // each; empty = raw inputs). Relative edge positions use the raw xy.
  void set_input_normalization(std::vector<double> mean, std::vector<double> inv_std);
  // With open edges every message has weight 1 (warm-up); the logits are still computed.
  void set_open_edges(bool open) { open_edges_ = open; }
  // Parameters in a fixed order (the flat layout).
  void Parameters(nn::ParameterList<T>& list);

 private:
  void BuildEdges(int batch);
  // edge_kl_weights_ per edge of a batch of `rows` entity rows (both columns of the 2-way logits)
  const Mat& EdgeKlWeights(Eigen::Index rows);

  GnnOptions options_;
  nn::Mlp<T> act_;                           // d_act: F -> M -> H
  nn::Linear<T> edge_send_;                  // first layer of [d_eff | d_pres], sender half (no bias)
  nn::Linear<T> edge_recv_;                  // receiver half with the bias
  std::unique_ptr<nn::Linear<T>> edge_rel_;  // relative position -> first layer (no bias)
  nn::Linear<T> eff_out_;                    // M -> H
  nn::Linear<T> pres_out_;                   // M -> 2 (class 0 = edge)
  nn::GruCell<T> gru_;                       // [h_int, h_act] -> H
  nn::Mlp<T> pred_;                          // d_pred: H -> M -> 2
  bool open_edges_ = false;
  std::vector<double> entity_weights_;
  std::vector<double> onset_clearance_;
  Mat input_mean_, input_inv_std_;  // 1 x F each (empty: no standardisation)
  Mat row_weights_;                 // (B*N) x 1 built from entity_weights_
  std::vector<double> edge_kl_weights_;
  Mat edge_kl_;                    // (B*N*(N-1)) x 2 built from edge_kl_weights_
  Eigen::Index edge_kl_rows_ = 0;  // the batch rows edge_kl_ was built for
  int edges_batch_ = -1;
  std::vector<int> senders_, receivers_;
  Mat log_prior_;  // 1 x 2: log p, log (1 - p)
};

extern template class GnnModel<float>;
extern template class GnnModel<double>;

}  // namespace srics::graph_service
