#include "graph_service/trainer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace srics::graph_service {

GnnOptions MakeGnnOptions(const config::GraphConfig& config, const GraphDataset& data) {
  GnnOptions o;
  o.num_entities = data.num_entities();
  o.input_dim = data.input_dim();
  o.hidden_dim = config.hidden_dim;
  o.mlp_hidden = config.mlp_hidden;
  o.delta_scale = config.delta_scale;
  o.edge_node_inputs = config.edge_node_inputs;
  o.edge_relative_scale = config.edge_relative_scale;
  o.edge_prior = config.edge_prior;
  o.kl_weight = config.kl_weight;
  o.temperature = config.gumbel_temperature;
  o.hard = config.hard_edges;
  o.gate_logit_decay = config.gate_logit_decay;
  o.onset_loss_weight = config.onset_loss_weight;
  o.onset_motion = config.onset_motion_m;
  return o;
}

double KlWeightAt(const config::GraphConfig& c, int64_t update) {
  if (update < c.warmup_updates) return 0.0;
  if (c.kl_ramp_updates <= 0) return c.kl_weight;
  const double f = static_cast<double>(update - c.warmup_updates + 1) / c.kl_ramp_updates;
  return c.kl_weight * std::min(1.0, f);
}

namespace {

// The model is built before the optimizer can list its parameters.
nn::Rng& Seeded(nn::Rng& rng) { return rng; }

// Appends the windows of `more` to `batch` (rows b * N + n stay in window order).
template <typename T>
void AppendWindows(const WindowBatch<T>& more, WindowBatch<T>* batch) {
  if (more.batch == 0) return;
  if (batch->batch == 0) {
    *batch = more;
    return;
  }
  for (int t = 0; t < batch->steps(); ++t) {
    for (auto [into, from] :
         {std::pair{&batch->inputs[t], &more.inputs[t]}, std::pair{&batch->deltas[t], &more.deltas[t]}}) {
      const Eigen::Index rows = into->rows();
      into->conservativeResize(rows + from->rows(), Eigen::NoChange);
      into->bottomRows(from->rows()) = *from;
    }
  }
  batch->batch += more.batch;
}

}  // namespace

GnnTrainer::GnnTrainer(const config::GraphConfig& config, const GraphDataset& data, uint64_t seed)
    : config_(config),
      data_(data),
      rng_(seed),
      model_(MakeGnnOptions(config, data), Seeded(rng_)),
      params_([this] {
        nn::ParameterList<float> list;
        model_.Parameters(list);
        return list;
      }()),
      optimizer_(params_, {.lr = config.learning_rate}),
      adam_(params_, {.lr = config.learning_rate}),
      onsets_at_a_distance_(static_cast<size_t>(data.graph_entities()), 0),
      onsets_while_moving_(static_cast<size_t>(data.graph_entities()) * data.graph_entities(), 0) {
  if (config.standardize_inputs) {
    // mean of x and of y over every entity and step of the training episodes, and one
    // standard deviation pooled over both axes (distances stay isotropic)
    double sum[2] = {0, 0}, sq[2] = {0, 0}, count = 0;
    for (int ep : data.train_episodes())
      for (int t = 0; t <= data.episode_steps(); ++t)
        for (int e = 0; e < data.num_entities(); ++e) {
          for (int a = 0; a < 2; ++a) {
            const double v = data.position(ep, t, e)[a];
            sum[a] += v;
            sq[a] += v * v;
          }
          count += 1;
        }
    std::vector<double> mean(data.input_dim(), 0.0), inv_std(data.input_dim(), 1.0);
    if (count > 0) {
      double var = 0;
      for (int a = 0; a < 2; ++a) {
        mean[a] = sum[a] / count;
        var += (sq[a] / count - mean[a] * mean[a]) / 2;
      }
      inv_std[0] = inv_std[1] = 1.0 / std::sqrt(std::max(var, 1e-12));
    }
    model_.set_input_normalization(mean, inv_std);
  }
  if (config.normalize_per_entity) {
    // 1 / variance of each entity's position change over the training episodes
    const int n = data.num_entities();
    std::vector<double> sq(n, 0.0);
    double count = 0;
    for (int ep : data.train_episodes()) {
      for (int t = 0; t < data.episode_steps(); ++t) {
        for (int e = 0; e < n; ++e) {
          for (int a = 0; a < 2; ++a) {
            const double d = data.position(ep, t + 1, e)[a] - data.position(ep, t, e)[a];
            sq[e] += d * d / 2;
          }
        }
        count += 1;
      }
    }
    // an entity whose variance is below 1% of the largest counts as static and keeps the
    // weight of the largest (not amplified by 1 / its near-zero variance). Neither this nor
    // weight 0 closes the edge arm -> static puck (see README, Status)
    double largest = 0;
    for (int e = 0; e < n; ++e) largest = std::max(largest, count > 0 ? sq[e] / count : 0.0);
    largest = std::max(largest, 1e-12);
    std::vector<double> w(n);
    for (int e = 0; e < n; ++e) {
      const double var = count > 0 ? sq[e] / count : 0.0;
      w[e] = 1.0 / (var < config.static_variance_fraction * largest ? largest : var);
    }
    model_.set_entity_loss_weights(w);
  }
  arm_ = SelectActionEntity(data);
  // onsets at a distance need every entity's size (SetContactRadii): without them (toy worlds)
  // a push cannot be told from a tie's pull, and weighting every onset opened object -> arm
  // and contact edges (the refinement test's roped pucks), so none is weighted until then
  model_.set_onset_loss_weight(0);
}

double GnnTrainer::Update() {
  // where the update stands in the warm-up / KL ramp schedule (RestartSchedule starts it anew)
  const int64_t phase = updates_ - schedule_start_;
  model_.set_kl_weight(KlWeightAt(config_, phase));
  model_.set_open_edges(phase < config_.warmup_updates);
  if (config_.use_adam && config_.restart_adam_after_warmup && config_.warmup_updates > 0 &&
      phase == config_.warmup_updates) {
    // the gates start: a fresh optimiser state. The gate parameters had no loss or KL
    // gradient during the warm-up (only gate_logit_decay's), so with the global step count
    // Adam's bias correction would make their first steps 3-6 times the learning rate, and
    // the second moments of that burst would slow the KL's later closing for
    // ~1 / (1 - beta2) updates
    adam_ = nn::Adam<float>(params_, {.lr = config_.learning_rate, .beta2 = config_.adam_beta2_after_warmup});
  }
  const int from_refinement =
      refine_ != nullptr && refine_->size() > 0
          ? std::clamp(static_cast<int>(std::lround(config_.batch_windows * refine_share_)), 0, config_.batch_windows)
          : 0;
  if (from_refinement < config_.batch_windows)
    data_.SampleWindows(config_.batch_windows - from_refinement, config_.window, rng_, &batch_);
  else
    batch_ = {};
  if (from_refinement > 0) {
    refine_->SampleWindows(from_refinement, config_.window, rng_, &refine_batch_);
    AppendWindows(refine_batch_, &batch_);
  }
  tape_.Reset();
  GnnModel<float>::Loss loss = model_.WindowLoss(tape_, batch_, rng_);
  optimizer_.ZeroGrad();
  tape_.Backward(loss.total);
  const double total = static_cast<double>(loss.total.value()(0, 0));
  ++updates_;
  if (!std::isfinite(total) || !nn::GradientsUsable(params_)) {
    // one such step would put NaN or an infinite moment into the model for good
    ++skipped_updates_;
    ++skipped_in_a_row_;
    const int limit = config_.max_skipped_updates_in_a_row;
    if (limit > 0 && skipped_in_a_row_ >= limit)
      throw GnnTrainingDivergedError(
          "graph learning diverged: the last " + std::to_string(skipped_in_a_row_) + " GNN updates (to update " +
          std::to_string(updates_) +
          ") all met a non-finite loss or an unusable gradient, so the model no "
          "longer changes; the service stops rather than publish its graph (graph.max_skipped_updates_in_a_row: " +
          std::to_string(limit) + ")");
    return std::numeric_limits<double>::quiet_NaN();
  }
  skipped_in_a_row_ = 0;
  if (config_.use_adam)
    adam_.Step();
  else
    optimizer_.Step();
  last_mse_ = loss.mse / batch_.steps();
  last_kl_ = loss.kl / batch_.steps();
  return total;
}

void GnnTrainer::SetRefinementData(const GraphDataset* data, double share) {
  if (data != nullptr && (data->num_entities() != data_.num_entities() || data->input_dim() != data_.input_dim() ||
                          data->episode_steps() < config_.window))
    throw std::invalid_argument("GnnTrainer: refinement data of another shape, or episodes shorter than a window");
  refine_ = data;
  refine_share_ = std::clamp(share, 0.0, 1.0);
}

std::vector<nn::CheckpointSection> GnnTrainer::SaveState() const {
  const std::string signature = nn::SignatureString(params_);
  nn::ByteWriter counters;
  counters.Put<int64_t>(updates_);
  counters.Put<double>(last_mse_);
  counters.Put<double>(last_kl_);
  counters.PutString(nn::RngState(rng_));
  counters.Put<int64_t>(schedule_start_);  // (absent from states written before refinement)
  return {{"gnn", signature, nn::Flatten(params_), ""},
          {"gnn.rmsprop", signature, optimizer_.ExportState(), ""},
          {"gnn.adam", signature, adam_.ExportState(), ""},
          {"gnn.trainer", "", {}, counters.Take()}};
}

void GnnTrainer::LoadState(const std::vector<nn::CheckpointSection>& sections, const std::string& path) {
  nn::LoadSection(nn::FindSection(sections, "gnn", path), params_, path);
  nn::ByteReader counters(nn::FindSection(sections, "gnn.trainer", path).bytes, path + ": gnn.trainer");
  const auto updates = counters.Get<int64_t>();
  // refinement trains on after max_updates
  const int64_t most = config_.refine_after_publish ? std::numeric_limits<int64_t>::max() : config_.max_updates;
  if (updates < 0 || updates > most)
    throw nn::CheckpointError(path + ": " + std::to_string(updates) + " GNN updates, outside 0.." +
                              std::to_string(most));
  last_mse_ = counters.Get<double>();
  last_kl_ = counters.Get<double>();
  nn::SetRngState(&rng_, counters.GetString(), path + ": gnn.trainer");
  const int64_t schedule_start = counters.done() ? 0 : counters.Get<int64_t>();
  if (schedule_start < 0 || schedule_start > updates)
    throw nn::CheckpointError(path + ": schedule start " + std::to_string(schedule_start) + " outside 0.." +
                              std::to_string(updates));
  if (config_.use_adam && config_.restart_adam_after_warmup && config_.warmup_updates > 0 &&
      updates - schedule_start > config_.warmup_updates) {
    // the optimiser Update restarts at the end of the warm-up, with its options
    adam_ = nn::Adam<float>(params_, {.lr = config_.learning_rate, .beta2 = config_.adam_beta2_after_warmup});
  }
  for (const auto& [name, state] : {std::pair{"gnn.rmsprop", 0}, std::pair{"gnn.adam", 1}}) {
    const nn::CheckpointSection& section = nn::FindSection(sections, name, path);
    try {
      if (state == 0)
        optimizer_.ImportState(section.values);
      else
        adam_.ImportState(section.values);
    } catch (const std::invalid_argument& e) {
      throw nn::CheckpointError(path + ": " + name + ": " + e.what());
    }
  }
  updates_ = updates;
  schedule_start_ = schedule_start;
}

void GnnTrainer::SetContactRadii(std::vector<double> radii) {
  contact_radius_ = std::move(radii);
  // counted once, on the data the training starts with: what the KL factors and the progress say
  CountOnsetsAtADistance();
  tie_evidence_counted_ = config_.tie_evidence_per_episode > 0 && !data_.combinations() && data_.size() > 0 && Sized();
  tied_by_evidence_ = TiedByEvidence();
  if (!tied_by_evidence_.empty() && config_.tie_kl_factor != 1) {
    const int n = data_.num_entities();
    std::vector<double> weights(static_cast<size_t>(n) * n, 1.0);
    for (const auto& [i, j] : tied_by_evidence_)
      weights[static_cast<size_t>(i) * n + j] = weights[static_cast<size_t>(j) * n + i] = config_.tie_kl_factor;
    model_.set_edge_kl_weights(std::move(weights));
  }
  if (config_.onset_loss_weight <= 0) return;
  const bool sized = Sized();
  model_.set_onset_loss_weight(sized ? config_.onset_loss_weight : 0);
  if (sized) model_.set_onset_clearance(OnsetClearance(contact_radius_));
}

std::vector<std::pair<int, int>> GnnTrainer::TiedByEvidence() const {
  std::vector<std::pair<int, int>> tied;
  if (!tie_evidence_counted_) return tied;
  const std::vector<int64_t>& onsets = onsets_at_a_distance_;
  const double needed = config_.tie_evidence_per_episode * data_.size();
  const size_t n = onsets.size();
  // each end starts at a distance often, and mostly while the other end moves (pulled by it)
  auto pulled_by = [&](size_t mover, size_t started) {
    return onsets[started] >= needed && static_cast<double>(onsets_while_moving_[mover * n + started]) >=
                                            config_.tie_evidence_share * static_cast<double>(onsets[started]);
  };
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      if (static_cast<int>(i) != arm_ && static_cast<int>(j) != arm_ && pulled_by(i, j) && pulled_by(j, i))
        tied.emplace_back(static_cast<int>(i), static_cast<int>(j));
  return tied;
}

std::vector<double> GnnTrainer::OnsetClearance(const std::vector<double>& graph_radius) const {
  const int n = data_.num_entities();
  std::vector<double> clearance(static_cast<size_t>(n) * n, 0.0);
  // the arm goes where the action sends it: its onsets need no cause (weighted, they only
  // invited object -> arm edges: random table 6, 0.07-0.12)
  for (int i = 0; i < n; ++i)
    if (i != arm_) clearance[static_cast<size_t>(i) * n + arm_] = std::numeric_limits<double>::infinity();
  if (graph_radius.size() != static_cast<size_t>(data_.graph_entities())) return clearance;
  // onsets of an object the arm touches are pushes: not weighted. The clearance is per
  // position in the episode; with combinations (positions hold different objects) each object
  // position takes the largest object's radius, which leaves out a few more onsets than needed.
  // The arm is graph entity 0 there (every combination starts with it).
  std::vector<double> radius(static_cast<size_t>(n));
  const double largest = *std::max_element(graph_radius.begin() + 1, graph_radius.end());
  for (int j = 0; j < n; ++j)
    radius[static_cast<size_t>(j)] = !data_.combinations() ? graph_radius[static_cast<size_t>(j)]
                                     : j == arm_           ? graph_radius[0]
                                                           : largest;
  // Nor those of an object another object touches (a sliding one running into it): weighted,
  // they opened the contact gates of relational-4's free puck to 0.06-0.08 even apart.
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j && j != arm_)
        clearance[static_cast<size_t>(i) * n + j] =
            radius[static_cast<size_t>(i)] + radius[static_cast<size_t>(j)] +
            (i == arm_ ? config_.contact_margin_m : config_.object_contact_margin_m);
  return clearance;
}

void GnnTrainer::CountOnsetsAtADistance() {
  const size_t graph_entities = static_cast<size_t>(data_.graph_entities());
  onsets_at_a_distance_.assign(graph_entities, 0);
  onsets_while_moving_.assign(graph_entities * graph_entities, 0);
  if (!Sized()) return;
  const int n = data_.num_entities();
  const std::vector<double> clearance = OnsetClearance(contact_radius_);
  // the loss's own rule on the loss's own inputs (float motions), whole episodes in chunks
  const float onset_sq = static_cast<float>(config_.onset_motion_m * config_.onset_motion_m);
  constexpr int kChunk = 64;
  WindowBatch<float> batch;
  for (int first = 0; first < data_.size(); first += kChunk) {
    std::vector<int> chunk(static_cast<size_t>(std::min(kChunk, data_.size() - first)));
    std::iota(chunk.begin(), chunk.end(), first);
    data_.EpisodeBatch(chunk, &batch);
    for (int t = 1; t < static_cast<int>(batch.deltas.size()); ++t)
      for (Eigen::Index r = 0; r < batch.deltas[t].rows(); ++r) {
        if (!OnsetAtADistance(batch.inputs[t], batch.deltas[t], batch.deltas[t - 1], r, n, clearance, onset_sq))
          continue;
        const int episode = chunk[static_cast<size_t>(r / n)], j = static_cast<int>(r % n);
        const size_t to = static_cast<size_t>(data_.graph_entity(episode, j));
        ++onsets_at_a_distance_[to];
        // which other object moves in that step: a tie's other end (the arm moves nearly always)
        for (int i = 0; i < n; ++i)
          if (i != j && i != arm_ && batch.deltas[t].row(r - j + i).squaredNorm() > onset_sq)
            ++onsets_while_moving_[static_cast<size_t>(data_.graph_entity(episode, i)) * graph_entities + to];
      }
  }
}

void GnnTrainer::RestartSchedule() { schedule_start_ = updates_; }

bool GnnTrainer::Settled() const {
  return updates_ - schedule_start_ > static_cast<int64_t>(config_.warmup_updates) + config_.kl_ramp_updates;
}

EdgeStatistics GnnTrainer::Evaluate() {
  const int n = data_.num_entities();
  // statistics are per graph entity: the catalogue's identities for a data set of
  // combinations (a pair's weight is its mean over the steps where both are present)
  const int g = data_.graph_entities();
  EdgeStatistics stats;
  stats.num_entities = g;
  // [0]: the random-action data set, [1]: the run's training episodes (refinement)
  std::vector<double> sum[2], pair_count[2];
  for (int d = 0; d < 2; ++d) sum[d].assign(static_cast<size_t>(g) * g, 0.0), pair_count[d].assign(sum[d].size(), 0.0);
  double mse = 0, zero_mse = 0, transitions = 0;
  std::vector<double> entity_mse(g, 0.0), entity_zero(g, 0.0), entity_transitions(g, 0.0);
  // the same noise at every evaluation, so that successive graphs differ by training only
  nn::Rng noise_rng(0x5eed);
  nn::Tape<float> tape;
  WindowBatch<float> batch;
  // the training and held-out splits, and the run's training episodes of a refinement (their
  // own edge weights; the held-out error stays that of the random-action episodes)
  struct Part {
    const GraphDataset* data;
    const std::vector<int>* episodes;
    bool held_out;
  };
  std::vector<Part> parts = {{&data_, &data_.train_episodes(), false}, {&data_, &data_.held_out_episodes(), true}};
  // object pairs apart (more than contact_margin_m beyond touching): their own means
  const bool apart = ApartWeights();
  std::vector<double> apart_sum(apart ? static_cast<size_t>(g) * g : 0, 0.0), apart_count(apart_sum.size(), 0.0);
  if (refine_ != nullptr && refine_->size() > 0) parts.push_back({refine_, &refine_->train_episodes(), false});
  for (const auto& [data, split, held_out] : parts) {
    for (size_t first = 0; first < split->size(); first += static_cast<size_t>(config_.eval_chunk_episodes)) {
      const size_t last = std::min(split->size(), first + config_.eval_chunk_episodes);
      const std::vector<int> chunk(split->begin() + first, split->begin() + last);
      data->EpisodeBatch(chunk, &batch);
      const int b = batch.batch;
      const Eigen::Index rows = static_cast<Eigen::Index>(b) * n;
      nn::Matrix<float> h = nn::Matrix<float>::Zero(rows, config_.hidden_dim);
      for (int t = 0; t < batch.steps(); ++t) {
        // one step per tape pass: the state is carried over as a constant
        tape.Reset();
        const nn::Matrix<float> noise = nn::RandomGumbel<float>(rows * (n - 1), 2, noise_rng);
        auto step = model_.Forward(tape, tape.Constant(h), tape.Constant(batch.inputs[t]), b, noise);
        h = step.hidden.value();
        const nn::Matrix<float>& logits = step.edge_logits.value();
        const Eigen::Index per_sample = static_cast<Eigen::Index>(n) * (n - 1);
        for (Eigen::Index e = 0; e < logits.rows(); ++e) {
          // probability of class 0 (edge) of the 2-way softmax
          const double p =
              1.0 / (1.0 + std::exp(static_cast<double>(logits(e, 1)) - static_cast<double>(logits(e, 0))));
          const int local = static_cast<int>(e % per_sample);
          const int ep = chunk[static_cast<size_t>(e / per_sample)];
          const size_t pair = static_cast<size_t>(data->graph_entity(ep, model_.edge_sender_entity(local))) * g +
                              data->graph_entity(ep, model_.edge_receiver_entity(local));
          const int d = data == refine_ ? 1 : 0;
          sum[d][pair] += p;
          pair_count[d][pair] += 1;
          if (apart && d == 0) {
            const Eigen::Index first_row = (e / per_sample) * n;
            const size_t sender = pair / static_cast<size_t>(g), receiver = pair % static_cast<size_t>(g);
            const double contact = contact_radius_[sender] + contact_radius_[receiver] + config_.contact_margin_m;
            if (ApartThroughTheStep(batch.inputs[t], batch.deltas[t], first_row + model_.edge_sender_entity(local),
                                    first_row + model_.edge_receiver_entity(local), contact)) {
              apart_sum[pair] += p;
              apart_count[pair] += 1;
            }
          }
        }
        if (held_out) {
          const nn::Matrix<float>& target = batch.deltas[t];
          // per transition: mean over the entities and axes of one window
          mse += (step.delta.value() - target).squaredNorm() / (2.0 * n);
          zero_mse += target.squaredNorm() / (2.0 * n);
          transitions += b;
          for (Eigen::Index r = 0; r < target.rows(); ++r) {
            const int entity = data->graph_entity(chunk[static_cast<size_t>(r / n)], static_cast<int>(r % n));
            entity_mse[entity] += (step.delta.value().row(r) - target.row(r)).squaredNorm() / 2;
            entity_zero[entity] += target.row(r).squaredNorm() / 2;
            entity_transitions[entity] += 1;
          }
        }
      }
    }
  }
  // a pair never present together has no evidence: weight 0 (no edge)
  auto means = [](const std::vector<double>& total, const std::vector<double>& count) {
    std::vector<double> mean(total.size(), 0.0);
    for (size_t i = 0; i < total.size(); ++i) mean[i] = count[i] > 0 ? total[i] / count[i] : 0;
    return mean;
  };
  stats.mean_weight = means(sum[0], pair_count[0]);
  if (apart) stats.apart_weight = means(apart_sum, apart_count);
  if (refine_ != nullptr && refine_->size() > 0) stats.training_mean_weight = means(sum[1], pair_count[1]);
  if (config_.readout == config::GraphReadout::kCut) stats.cut_score = EdgeCutScores();
  stats.held_out_mse = transitions > 0 ? mse / transitions : 0;
  stats.held_out_zero_mse = transitions > 0 ? zero_mse / transitions : 0;
  for (int e = 0; e < g; ++e) {
    stats.held_out_entity_mse.push_back(entity_transitions[e] > 0 ? entity_mse[e] / entity_transitions[e] : 0);
    stats.held_out_entity_zero_mse.push_back(entity_transitions[e] > 0 ? entity_zero[e] / entity_transitions[e] : 0);
  }
  stats.tie_evidence_counted = tie_evidence_counted_;
  stats.tied_by_evidence = tied_by_evidence_;
  return stats;
}

std::vector<double> GnnTrainer::HeldOutEntityError(int cut_sender, int cut_receiver) {
  const int n = data_.num_entities();
  const std::vector<int>& episodes = data_.held_out_episodes();
  std::vector<double> error(n, 0.0);
  double transitions = 0;
  // the same noise in every call: two calls differ only by the cut
  nn::Rng noise_rng(0xC07);
  nn::Tape<float> tape;
  WindowBatch<float> batch;
  std::vector<int> senders;
  for (size_t first = 0; first < episodes.size(); first += static_cast<size_t>(config_.eval_chunk_episodes)) {
    const size_t last = std::min(episodes.size(), first + config_.eval_chunk_episodes);
    const std::vector<int> chunk(episodes.begin() + first, episodes.begin() + last);
    data_.EpisodeBatch(chunk, &batch);
    const int b = batch.batch;
    const Eigen::Index rows = static_cast<Eigen::Index>(b) * n;
    const bool cut = cut_sender >= 0 && b > 1;
    if (cut) {
      // the edge of sample s takes its sender from sample s + b/2 (a derangement): the
      // message keeps its usual values but no longer depends on this sample's sender. (Forcing
      // the message to zero instead also removes its constant part, which every edge of a
      // dense model carries and the receiver relies on.) Edges of receiver row r are
      // r * (N - 1) + k, senders in increasing order without r.
      senders = model_.senders(b);
      const int k = cut_sender < cut_receiver ? cut_sender : cut_sender - 1;
      for (int s = 0; s < b; ++s)
        senders[(static_cast<size_t>(s) * n + cut_receiver) * (n - 1) + k] = ((s + b / 2) % b) * n + cut_sender;
    }
    nn::Matrix<float> h = nn::Matrix<float>::Zero(rows, config_.hidden_dim);
    for (int t = 0; t < batch.steps(); ++t) {
      tape.Reset();
      const nn::Matrix<float> noise = nn::RandomGumbel<float>(rows * (n - 1), 2, noise_rng);
      auto step =
          model_.Forward(tape, tape.Constant(h), tape.Constant(batch.inputs[t]), b, noise, cut ? &senders : nullptr);
      h = step.hidden.value();
      const nn::Matrix<float>& target = batch.deltas[t];
      for (Eigen::Index r = 0; r < target.rows(); ++r)
        error[r % n] += (step.delta.value().row(r) - target.row(r)).squaredNorm() / 2;
      transitions += b;
    }
  }
  for (double& e : error) e = transitions > 0 ? e / transitions : 0;
  return error;
}

std::vector<bool> MovingEntities(const std::vector<double>& no_motion_error, double fraction) {
  const double largest =
      no_motion_error.empty() ? 0 : *std::max_element(no_motion_error.begin(), no_motion_error.end());
  std::vector<bool> moving;
  for (double e : no_motion_error) moving.push_back(e > fraction * largest);
  return moving;
}

std::vector<double> GnnTrainer::EdgeCutScores() {
  const int n = data_.num_entities();
  std::vector<double> score(static_cast<size_t>(n) * n, 0.0);
  // what there is to predict per entity: the held-out error of predicting no motion
  std::vector<double> zero(n, 0.0);
  for (int ep : data_.held_out_episodes())
    for (int t = 0; t < data_.episode_steps(); ++t)
      for (int e = 0; e < n; ++e)
        for (int a = 0; a < 2; ++a) {
          const double d = data_.position(ep, t + 1, e)[a] - data_.position(ep, t, e)[a];
          zero[e] += d * d / 2;
        }
  const std::vector<bool> moving = MovingEntities(zero, config_.static_variance_fraction);
  const std::vector<double> full = HeldOutEntityError(-1, -1);
  for (int j = 0; j < n; ++j) {
    // an entity that does not move has nothing for an edge to explain
    if (!moving[j]) continue;
    const double transitions = static_cast<double>(data_.held_out_episodes().size()) * data_.episode_steps();
    const double explained = zero[j] / transitions - full[j];
    if (!(explained > 0)) continue;
    for (int i = 0; i < n; ++i) {
      if (i == j) continue;
      const double lost = HeldOutEntityError(i, j)[j] - full[j];
      score[static_cast<size_t>(i) * n + j] = std::clamp(lost / explained, 0.0, 1.0);
    }
  }
  return score;
}

}  // namespace srics::graph_service
