#include "graph_service/gnn_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "common/nn/optim.h"
#include "graph_service/trainer.h"
#include "tests/common/nn/gradcheck.h"
#include "tests/graph_service/toy_world.h"

namespace srics::graph_service {
namespace {

using testing::ToyWorld;

GraphDataset ToyData(int episodes, int steps) {
  ToyWorld world({.num_pucks = 2, .steps = steps});
  GraphDataset data = GraphDataset::ShapedLike(world.RandomEpisode(0));
  for (int e = 0; e < episodes; ++e) EXPECT_EQ(data.Add(world.RandomEpisode(100 + e)), "");
  data.Split(0.25, 1);
  return data;
}

// ToyData, a generator from `seed` and a batch of windows drawn with it (the model under test
// is then initialised from the same generator).
template <typename T>
struct ToyBatch {
  ToyBatch(int episodes, int steps, uint64_t seed, int windows, int window_steps)
      : data(ToyData(episodes, steps)), rng(seed) {
    data.SampleWindows(windows, window_steps, rng, &batch);
  }
  GraphDataset data;
  nn::Rng rng;
  WindowBatch<T> batch;
};

TEST(GnnModelTest, EdgeIndexingIsConsistent) {
  nn::Rng rng(1);
  GnnModel<float> model({.num_entities = 4, .input_dim = 8, .hidden_dim = 3, .mlp_hidden = 5}, rng);
  const auto& s = model.senders(2);
  const auto& r = model.receivers(2);
  ASSERT_EQ(s.size(), 2u * 4 * 3);
  for (size_t e = 0; e < s.size(); ++e) {
    EXPECT_NE(s[e], r[e]);
    EXPECT_EQ(s[e] / 4, r[e] / 4);  // same sample
    EXPECT_EQ(model.edge_sender_entity(static_cast<int>(e)), s[e] % 4);
    EXPECT_EQ(model.edge_receiver_entity(static_cast<int>(e)), r[e] % 4);
  }
}

TEST(GnnModelTest, HardSamplesAreZeroOrOne) {
  ToyBatch<float> toy(4, 6, /*seed=*/2, 3, 4);
  auto& data = toy.data;  // not a structured binding: clang 14 cannot capture one
  auto& rng = toy.rng;
  auto& batch = toy.batch;
  GnnModel<float> model(
      {.num_entities = 3, .input_dim = data.input_dim(), .hidden_dim = 6, .mlp_hidden = 8, .hard = true}, rng);
  nn::Tape<float> tape;
  auto h = tape.Constant(nn::Tensor::Zero(9, 6));
  auto step = model.Forward(tape, h, tape.Constant(batch.inputs[0]), 3, nn::RandomGumbel<float>(18, 2, rng));
  for (Eigen::Index e = 0; e < step.edge_weight.rows(); ++e) {
    const float w = step.edge_weight.value()(e, 0);
    EXPECT_TRUE(w == 0.f || w == 1.f) << w;
  }
  EXPECT_EQ(step.delta.rows(), 9);
  EXPECT_EQ(step.delta.cols(), 2);
}

// The largest gap between the window loss's gradients and central differences, after moving
// every parameter off zero: with h(0) = 0 and zero biases every edge pre-activation would sit on
// the relu kink, where finite differences are meaningless. The same Gumbel noise every time.
double WindowLossGradientError(GnnModel<double>& model, const WindowBatch<double>& batch, nn::Rng& rng) {
  nn::ParameterList<double> params;
  model.Parameters(params);
  for (nn::Parameter<double>* p : params)
    p->value += 0.3 * nn::RandomNormal<double>(p->value.rows(), p->value.cols(), rng);
  return nn::testing::GradCheck(params, [&](nn::Tape<double>& tape) {
    nn::Rng noise(11);
    return model.WindowLoss(tape, batch, noise).total;
  });
}

// Gradients of the whole model (soft edge samples, KL included) against central differences.
// A small model for the toy batch's entities, soft edges, the KL term on.
GnnOptions SmallGradientOptions(const ToyBatch<double>& toy) {
  GnnOptions o;
  o.num_entities = 3;
  o.input_dim = toy.data.input_dim();
  o.hidden_dim = 3;
  o.mlp_hidden = 4;
  o.kl_weight = 0.1;
  o.hard = false;
  return o;
}

TEST(GnnModelTest, GradientsMatchFiniteDifferences) {
  ToyBatch<double> toy(4, 6, /*seed=*/3, 2, 3);
  GnnModel<double> model(SmallGradientOptions(toy), toy.rng);
  nn::ParameterList<double> params;
  model.Parameters(params);
  ASSERT_GT(params.size(), 10u);
  EXPECT_LT(WindowLossGradientError(model, toy.batch, toy.rng), 1e-6);
}

// The same with the options of the default GraphConfig: node inputs and relative positions
// on the edges, standardised inputs, per-entity loss weights and the gate-logit decay.
TEST(GnnModelTest, GradientsMatchFiniteDifferencesWithEdgeInputs) {
  ToyBatch<double> toy(4, 6, /*seed=*/5, 2, 3);
  GnnOptions options = SmallGradientOptions(toy);
  options.edge_node_inputs = true;
  options.edge_relative_scale = 0.2;
  options.gate_logit_decay = 0.5;
  GnnModel<double> model(options, toy.rng);
  std::vector<double> mean(toy.data.input_dim(), 0.1), inv_std(toy.data.input_dim(), 2.0);
  model.set_input_normalization(mean, inv_std);
  model.set_entity_loss_weights({1.0, 2.0, 0.5});
  EXPECT_LT(WindowLossGradientError(model, toy.batch, toy.rng), 1e-6);
}

// Per-edge KL factors: all 1 is the plain KL, bit for bit; 0.5 on every edge halves it exactly
// (a power of two); 0 on one edge removes that edge's share, and the squared error never moves.
// Gradients stay exact with factors (the tied pair's edges 1 <-> 2 at 0.25).
TEST(GnnModelTest, EdgeKlWeightsScaleEachEdgesKl) {
  ToyBatch<double> toy(4, 6, /*seed=*/3, 2, 3);
  GnnModel<double> model(SmallGradientOptions(toy), toy.rng);
  auto loss = [&](std::vector<double> weights) {
    model.set_edge_kl_weights(std::move(weights));
    nn::Tape<double> tape;
    nn::Rng noise(11);
    return model.WindowLoss(tape, toy.batch, noise);
  };
  const auto plain = loss({});
  ASSERT_GT(plain.kl, 0);
  const auto ones = loss(std::vector<double>(9, 1.0));
  EXPECT_EQ(ones.kl, plain.kl);
  EXPECT_EQ(ones.mse, plain.mse);  // (total is a node of the lambda's tape, gone by now)
  const auto halves = loss(std::vector<double>(9, 0.5));
  EXPECT_EQ(halves.kl, 0.5 * plain.kl);
  EXPECT_EQ(halves.mse, plain.mse);
  std::vector<double> without_one(9, 1.0);
  without_one[1 * 3 + 2] = 0;  // the edge 1 -> 2
  const auto fewer = loss(without_one);
  EXPECT_LT(fewer.kl, plain.kl);
  EXPECT_GT(fewer.kl, 0);
  EXPECT_EQ(fewer.mse, plain.mse);
  EXPECT_THROW(loss(std::vector<double>(4, 1.0)), std::invalid_argument);
  std::vector<double> tied(9, 1.0);
  tied[1 * 3 + 2] = tied[2 * 3 + 1] = 0.25;
  model.set_edge_kl_weights(tied);
  EXPECT_LT(WindowLossGradientError(model, toy.batch, toy.rng), 1e-6);
}

// Segment distances by hand: crossing paths 0; parallel ones their offset; an end point's
// distance to the other segment's interior; and the case the end points miss: the hand runs
// from 13 cm below an object at rest to 4.5 cm beyond it (clear at both ends, through it
// in between).
TEST(GnnModelTest, SegmentDistanceByHand) {
  EXPECT_EQ(SegmentDistance(0, 0, 1, 1, 0, 1, 1, 0), 0.0);
  EXPECT_NEAR(SegmentDistance(0, 0, 1, 0, 0, 0.3, 1, 0.3), 0.3, 1e-15);
  EXPECT_NEAR(SegmentDistance(0, 0, 1, 0, 0.5, 0.2, 0.5, 1), 0.2, 1e-15);
  EXPECT_NEAR(SegmentDistance(0, 0, 0, 0, 3, 4, 3, 4), 5.0, 1e-15);  // two points
  EXPECT_NEAR(SegmentDistance(0, -0.13, 0, 0.045, 0, 0, 0, 0), 0.0, 1e-15);
  nn::Matrix<double> x(2, 2), dx(2, 2);
  x << 0, -0.13, 0, 0;
  dx << 0, 0.175, 0, 0;
  EXPECT_FALSE(ApartThroughTheStep(x, dx, 0, 1, 0.04));
  dx << 0.1, 0.175, 0, 0;  // 10 cm to the side at the end: passes 6.4 cm from it
  EXPECT_NEAR(SegmentDistance(0, -0.13, 0.1, 0.045, 0, 0, 0, 0), 0.13 * 0.1 / std::hypot(0.1, 0.175), 1e-12);
  EXPECT_TRUE(ApartThroughTheStep(x, dx, 0, 1, 0.04));
}

// The onset weight against a sum computed by hand from the model's own per-step predictions:
// mse(w) = mse(0) + w * sum over onset rows (moving now, not in the step before, of an entity
// whose onsets count) of entity weight * squared error / (rows * 2).
TEST(GnnModelTest, OnsetWeightCountsOnlyOnsets) {
  const int n = 3, b = 2, steps = 4;
  WindowBatch<double> batch;
  batch.batch = b;
  batch.num_entities = n;
  const int input_dim = 2 + 3 + 2;  // xy, 3 kinds, 2 action components
  for (int t = 0; t < steps; ++t) {
    nn::Matrix<double> x = nn::Matrix<double>::Zero(b * n, input_dim);
    nn::Matrix<double> d = nn::Matrix<double>::Zero(b * n, 2);
    for (int w = 0; w < b; ++w)
      for (int e = 0; e < n; ++e) {
        x(w * n + e, 0) = 0.2 * e;  // entities 0.2 m apart along x
        x(w * n + e, 1) = 0.05 * w;
        x(w * n + e, 2 + e) = 1;
        x(w * n + e, 5) = 0.1 * t - 0.1 * w;
      }
    batch.inputs.push_back(x);
    batch.deltas.push_back(d);
  }
  // window 0, entity 2: still at t = 0, 1, moving from t = 2 (an onset at t = 2 only)
  batch.deltas[2](2, 0) = 0.01;
  batch.deltas[3](2, 0) = 0.012;
  // window 1, entity 1: moving at t = 0 already (the window's first step is never an onset)
  // and t = 1; stops, starts again at t = 3 (an onset)
  batch.deltas[0](n + 1, 1) = 0.02;
  batch.deltas[1](n + 1, 1) = 0.02;
  batch.deltas[3](n + 1, 1) = -0.015;
  nn::Rng init(7);
  GnnModel<double> model({.num_entities = n,
                          .input_dim = input_dim,
                          .hidden_dim = 3,
                          .mlp_hidden = 4,
                          .edge_relative_scale = 0.05,
                          .kl_weight = 0.1,
                          .hard = false},
                         init);
  const std::vector<double> entity_weight = {1.0, 2.0, 0.5};
  model.set_entity_loss_weights(entity_weight);
  auto mse = [&](double onset_weight) {
    model.set_onset_loss_weight(onset_weight);
    nn::Tape<double> tape;
    nn::Rng noise(3);
    return model.WindowLoss(tape, batch, noise).mse;
  };
  // the squared errors per row and step, the model stepped by hand with the same noise
  std::vector<nn::Matrix<double>> sq;
  {
    nn::Tape<double> tape;
    nn::Rng noise(3);
    nn::Var<double> h = tape.Constant(nn::Matrix<double>::Zero(b * n, 3));
    for (int t = 0; t < steps; ++t) {
      auto step = model.Forward(tape, h, tape.Constant(batch.inputs[t]), b,
                                nn::RandomGumbel<double>(b * n * (n - 1), 2, noise));
      h = step.hidden;
      sq.push_back((step.delta.value() - batch.deltas[t]).array().square().matrix());
    }
  }
  const double rows2 = b * n * 2;
  const double onset_sum = (entity_weight[2] * sq[2].row(2).sum() + entity_weight[1] * sq[3].row(n + 1).sum()) / rows2;
  ASSERT_GT(onset_sum, 0);
  const double base = mse(0);
  EXPECT_NEAR(mse(4) - base, 4 * onset_sum, 1e-12);
  EXPECT_NEAR(mse(10) - base, 10 * onset_sum, 1e-12);
  // entity 1's onsets do not count (as the arm's in training: an infinite clearance around
  // it): only window 0's onset of 2
  std::vector<double> clearance(n * n, 0.0);
  clearance[2 * n + 1] = std::numeric_limits<double>::infinity();
  model.set_onset_clearance(clearance);
  EXPECT_NEAR(mse(4) - base, 4 * entity_weight[2] * sq[2].row(2).sum() / rows2, 1e-12);
  // finite clearances instead (entities sit 0.2 m apart along x): entity 0 within 0.25 m of
  // entity 1 takes away its onset, 0.35 m around entity 2 from entity 0 (0.4 m away) does not
  clearance[2 * n + 1] = 0;
  clearance[0 * n + 1] = 0.25;
  clearance[0 * n + 2] = 0.35;
  model.set_onset_clearance(clearance);
  EXPECT_NEAR(mse(4) - base, 4 * entity_weight[2] * sq[2].row(2).sum() / rows2, 1e-12);
  // 0.45 m around entity 2 as well: no onset counts
  clearance[0 * n + 2] = 0.45;
  model.set_onset_clearance(clearance);
  EXPECT_NEAR(mse(4), base, 1e-12);
}

TEST(GnnModelTest, LossGoesDownOnAFixedBatch) {
  ToyBatch<float> toy(8, 20, /*seed=*/4, 20, 10);
  auto& data = toy.data;  // not a structured binding: clang 14 cannot capture one
  auto& rng = toy.rng;
  auto& batch = toy.batch;
  GnnModel<float> model({.num_entities = 3, .input_dim = data.input_dim(), .hidden_dim = 10, .mlp_hidden = 32}, rng);
  nn::ParameterList<float> params;
  model.Parameters(params);
  nn::RmsProp<float> opt(params, {.lr = 1e-3});
  nn::Tape<float> tape;
  auto loss_now = [&] {
    nn::Rng noise(5);
    tape.Reset();
    return model.WindowLoss(tape, batch, noise);
  };
  const double before = loss_now().mse;
  for (int i = 0; i < 150; ++i) {
    tape.Reset();
    auto loss = model.WindowLoss(tape, batch, rng);
    opt.ZeroGrad();
    tape.Backward(loss.total);
    opt.Step();
  }
  const double after = loss_now().mse;
  EXPECT_LT(after, 0.2 * before) << before << " -> " << after;
}

// A trainer's config small enough for the toy data of these tests.
config::GraphConfig SmallTrainerConfig() {
  config::GraphConfig config;
  config.hidden_dim = 6;
  config.mlp_hidden = 12;
  config.batch_windows = 4;
  config.window = 5;
  return config;
}

// 60 random episodes of 40 steps of a toy world with `num_pucks` pucks and these ropes, split.
GraphDataset RandomToyEpisodes(int num_pucks, std::vector<std::pair<int, int>> ropes) {
  ToyWorld world({.num_pucks = num_pucks, .ropes = std::move(ropes), .steps = 40});
  GraphDataset data = GraphDataset::ShapedLike(world.RandomEpisode(0));
  for (int e = 0; e < 60; ++e) EXPECT_EQ(data.Add(world.RandomEpisode(300 + e)), "");
  data.Split(0.25, 1);
  return data;
}

TEST(GnnTrainerTest, EvaluationAveragesEdgeProbabilities) {
  GraphDataset data = ToyData(8, 10);
  config::GraphConfig config = SmallTrainerConfig();
  config.eval_chunk_episodes = 3;  // chunks of different sizes
  GnnTrainer trainer(config, data, 9);
  const EdgeStatistics a = trainer.Evaluate();
  const EdgeStatistics b = trainer.Evaluate();
  ASSERT_EQ(a.mean_weight.size(), 9u);
  EXPECT_EQ(a.mean_weight, b.mean_weight);  // evaluation is deterministic
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(a.mean_weight[i * 3 + i], 0.0);
    for (int j = 0; j < 3; ++j)
      if (i != j) EXPECT_TRUE(a.mean_weight[i * 3 + j] > 0 && a.mean_weight[i * 3 + j] < 1);
  }
  EXPECT_GT(a.held_out_zero_mse, 0);
  trainer.Update();
  EXPECT_EQ(trainer.updates(), 1);
  EXPECT_NE(trainer.Evaluate().mean_weight, a.mean_weight);
}

// The model's parameters, optimiser moments, as raw bytes (NaN compares equal to itself).
std::vector<std::vector<unsigned char>> ModelAndOptimiserBytes(const GnnTrainer& trainer) {
  std::vector<std::vector<unsigned char>> out;
  for (const nn::CheckpointSection& section : trainer.SaveState()) {
    if (section.name == "gnn.trainer") continue;  // the update count goes on
    const auto* bytes = reinterpret_cast<const unsigned char*>(section.values.data());
    out.emplace_back(bytes, bytes + section.values.size() * sizeof(float));
  }
  return out;
}

// A batch with a non-finite loss (a NaN put into the model, as a diverged step would) changes
// no parameter and no optimiser moment, counts as skipped, and a run of
// graph.max_skipped_updates_in_a_row of them ends training with an error naming the key; a
// good update in between starts the run afresh.
TEST(GnnTrainerTest, SkipsUnusableUpdatesAndStopsAfterTooManyInARow) {
  GraphDataset data = ToyData(8, 10);
  config::GraphConfig config = SmallTrainerConfig();
  config.max_skipped_updates_in_a_row = 3;
  GnnTrainer trainer(config, data, 9);
  EXPECT_TRUE(std::isfinite(trainer.Update()));
  const std::vector<nn::CheckpointSection> good = trainer.SaveState();
  nn::ParameterList<float> params;
  trainer.model().Parameters(params);
  auto poison = [&] {
    for (nn::Parameter<float>* p : params) p->value(0, 0) = std::numeric_limits<float>::quiet_NaN();
  };
  poison();
  const auto poisoned = ModelAndOptimiserBytes(trainer);
  EXPECT_TRUE(std::isnan(trainer.Update()));
  EXPECT_TRUE(std::isnan(trainer.Update()));
  EXPECT_EQ(ModelAndOptimiserBytes(trainer), poisoned);
  EXPECT_EQ(trainer.updates(), 3);
  EXPECT_EQ(trainer.skipped_updates(), 2);
  EXPECT_EQ(trainer.skipped_in_a_row(), 2);

  trainer.LoadState(good, "good state");  // the model as it was: learning again
  EXPECT_TRUE(std::isfinite(trainer.Update()));
  EXPECT_EQ(trainer.skipped_in_a_row(), 0);
  EXPECT_EQ(trainer.skipped_updates(), 2);

  poison();
  EXPECT_TRUE(std::isnan(trainer.Update()));
  EXPECT_TRUE(std::isnan(trainer.Update()));
  try {
    trainer.Update();
    FAIL() << "a third skipped update in a row did not end training";
  } catch (const GnnTrainingDivergedError& e) {
    EXPECT_NE(std::string(e.what()).find("graph.max_skipped_updates_in_a_row: 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("the last 3 GNN updates"), std::string::npos) << e.what();
  }
  EXPECT_EQ(trainer.skipped_updates(), 5);

  config.max_skipped_updates_in_a_row = 0;  // never ends
  GnnTrainer patient(config, data, 9);
  nn::ParameterList<float> patient_params;
  patient.model().Parameters(patient_params);
  for (nn::Parameter<float>* p : patient_params) p->value(0, 0) = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(std::isnan(patient.Update()));
  EXPECT_EQ(patient.skipped_in_a_row(), 10);
}

// Object pairs apart: with zero radii and margin every step counts (the plain means), with radii
// larger than the table none does (0), and without radii or with object_edges every_step there
// are none.
TEST(GnnTrainerTest, ApartWeightsCountOnlyStepsBeyondContact) {
  GraphDataset data = ToyData(8, 10);
  config::GraphConfig config;
  config.hidden_dim = 6;
  config.mlp_hidden = 12;
  config.eval_chunk_episodes = 3;
  config.contact_margin_m = 0;
  config.object_edges = config::ObjectEdgeReadout::kApart;
  GnnTrainer trainer(config, data, 9);
  EXPECT_FALSE(trainer.ApartWeights());
  EXPECT_TRUE(trainer.Evaluate().apart_weight.empty());
  trainer.SetContactRadii({0, 0, 0});
  ASSERT_TRUE(trainer.ApartWeights());
  const EdgeStatistics every = trainer.Evaluate();
  ASSERT_EQ(every.apart_weight.size(), 9u);
  for (size_t k = 0; k < 9; ++k) EXPECT_NEAR(every.apart_weight[k], every.mean_weight[k], 1e-12) << k;
  trainer.SetContactRadii({10, 10, 10});
  for (double w : trainer.Evaluate().apart_weight) EXPECT_EQ(w, 0.0);
  config.object_edges = config::ObjectEdgeReadout::kEveryStep;
  GnnTrainer paper(config, data, 9);
  paper.SetContactRadii({0, 0, 0});
  EXPECT_FALSE(paper.ApartWeights());
  EXPECT_TRUE(paper.Evaluate().apart_weight.empty());
}

// The data's evidence of a tie: with a rope between the pucks, random actions start some puck
// moving with nothing in reach (the rope drags it); without one, every puck's motion starts at
// the arm (a push) and none counts. The arm's own onsets never count, and without the
// entities' radii there is nothing to tell (zeros).
TEST(GnnTrainerTest, OnsetsAtADistanceAreTheTiesEvidence) {
  auto onsets = [](std::vector<std::pair<int, int>> ropes, std::vector<double> radii) {
    const GraphDataset data = RandomToyEpisodes(2, std::move(ropes));
    GnnTrainer trainer(SmallTrainerConfig(), data, 3);
    if (!radii.empty()) trainer.SetContactRadii(radii);
    return trainer.onsets_at_a_distance();
  };
  const std::vector<double> radii = {0.03, 0.04, 0.04};  // the toy world's arm and pucks
  const std::vector<int64_t> roped = onsets({{1, 2}}, radii);
  ASSERT_EQ(roped.size(), 3u);
  EXPECT_EQ(roped[0], 0);
  EXPECT_GT(roped[1] + roped[2], 0);
  EXPECT_EQ(onsets({}, radii), (std::vector<int64_t>{0, 0, 0}));
  EXPECT_EQ(onsets({{1, 2}}, {}), (std::vector<int64_t>{0, 0, 0}));
}

// Ties seen in the data lower the KL of their pair only: with a rope between pucks 1 and 2 the
// pair starts moving at a distance and is picked; the free puck 3 and the arm never are; without
// the rope, or with the option off (no evidence threshold), no pair. A threshold above what the
// rope produces picks nothing. A KL factor of 1 still names the pair (the read-out's bar uses it;
// before, it hid the evidence). Counted only with every entity's radius; Evaluate passes both on.
TEST(GnnTrainerTest, TiedByEvidenceNamesThePairsThatStartMovingAtADistance) {
  auto tied = [](std::vector<std::pair<int, int>> ropes, double per_episode, double factor) {
    const GraphDataset data = RandomToyEpisodes(3, std::move(ropes));
    config::GraphConfig config = SmallTrainerConfig();
    config.tie_evidence_per_episode = per_episode;
    config.tie_kl_factor = factor;
    GnnTrainer trainer(config, data, 3);
    EXPECT_FALSE(trainer.tie_evidence_counted()) << "counted before the sizes are known";
    trainer.SetContactRadii({0.03, 0.04, 0.04, 0.04});  // the toy world's arm and pucks
    EXPECT_EQ(trainer.tie_evidence_counted(), per_episode > 0);
    const EdgeStatistics stats = trainer.Evaluate();
    EXPECT_EQ(stats.tie_evidence_counted, trainer.tie_evidence_counted());
    EXPECT_EQ(stats.tied_by_evidence, trainer.tied_by_evidence());
    const std::vector<int64_t> onsets = trainer.onsets_at_a_distance();
    return std::make_tuple(trainer.tied_by_evidence(), onsets, trainer.onsets_while_moving());
  };
  const auto [roped, onsets, while_moving] = tied({{1, 2}}, 1.0 / 60, 0.5);  // at least one onset each
  ASSERT_EQ(onsets.size(), 4u);
  ASSERT_GT(std::min(onsets[1], onsets[2]), 0) << "the toy rope shows no evidence on one end";
  EXPECT_EQ(onsets[3], 0);
  // by the object moving in that step: a rope's end starts while the other end moves (pulled),
  // far more often than beside the free puck; the arm is never the partner
  ASSERT_EQ(while_moving.size(), 16u);
  auto pair = [&while_moving = while_moving](int i, int j) {
    return while_moving[i * 4 + j] + while_moving[j * 4 + i];
  };
  EXPECT_GT(pair(1, 2), 2 * (pair(1, 3) + pair(2, 3)));
  EXPECT_GE(pair(1, 2), std::min(onsets[1], onsets[2]));
  for (int j = 0; j < 4; ++j) EXPECT_EQ(while_moving[j], 0) << "the arm counted as the partner of " << j;
  for (int i = 0; i < 4; ++i) EXPECT_EQ(while_moving[i * 4 + i], 0);
  EXPECT_EQ(roped, (std::vector<std::pair<int, int>>{{1, 2}}));
  EXPECT_TRUE(std::get<0>(tied({}, 1.0 / 60, 0.5)).empty());
  EXPECT_EQ(std::get<0>(tied({{1, 2}}, 1.0 / 60, 1.0)), (std::vector<std::pair<int, int>>{{1, 2}}));
  EXPECT_TRUE(std::get<0>(tied({{1, 2}}, 0, 0.5)).empty());
  const double above = (static_cast<double>(std::max(onsets[1], onsets[2])) + 1) / 60;
  EXPECT_TRUE(std::get<0>(tied({{1, 2}}, above, 0.5)).empty());
  // without every entity's radius nothing is counted: no pair named, and no bar per pair
  const GraphDataset data = RandomToyEpisodes(3, {{1, 2}});
  GnnTrainer unsized(SmallTrainerConfig(), data, 3);
  unsized.SetContactRadii({0.03, 0.04, 0.04});  // one short
  EXPECT_FALSE(unsized.tie_evidence_counted());
  EXPECT_TRUE(unsized.tied_by_evidence().empty());
  EXPECT_FALSE(unsized.Evaluate().tie_evidence_counted);
}

// Two ties on one table (ropes 1-2 and 3-4): all four pucks start moving at a distance, so
// counts per object alone (tie_evidence_share 0) pair every two of them; a tie's end starts
// while its own partner moves, which picks the two ropes only.
TEST(GnnTrainerTest, TiedByEvidenceTellsTwoTiesApart) {
  const GraphDataset data = RandomToyEpisodes(4, {{1, 2}, {3, 4}});
  auto tied = [&data](double share) {
    config::GraphConfig config = SmallTrainerConfig();
    config.tie_evidence_per_episode = 1.0 / 60;
    config.tie_kl_factor = 0.5;
    config.tie_evidence_share = share;
    GnnTrainer trainer(config, data, 3);
    trainer.SetContactRadii({0.03, 0.04, 0.04, 0.04, 0.04});
    const std::vector<int64_t>& onsets = trainer.onsets_at_a_distance();
    EXPECT_GT(*std::min_element(onsets.begin() + 1, onsets.end()), 0) << "a toy rope's end never pulled";
    return trainer.tied_by_evidence();
  };
  EXPECT_EQ(tied(0.5), (std::vector<std::pair<int, int>>{{1, 2}, {3, 4}}));
  EXPECT_EQ(tied(0).size(), 6u) << "counts per object pair every two tied objects";
}

// The onset weight needs every entity's size to tell a push from a pull at a distance: without
// radii (toy worlds) a trainer with onset_loss_weight trains exactly as one without; once the
// radii are set it weights onsets (its losses differ). Before, every onset was weighted without
// radii, pushes included (the refinement test's roped pucks got object -> arm edges).
TEST(GnnTrainerTest, OnsetWeightWaitsForTheEntitiesSizes) {
  GraphDataset data = ToyData(8, 10);
  config::GraphConfig config = SmallTrainerConfig();
  config.onset_loss_weight = 0;
  GnnTrainer plain(config, data, 9);
  config.onset_loss_weight = 30;
  GnnTrainer weighted(config, data, 9);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(weighted.Update(), plain.Update()) << "update " << i;
  weighted.SetContactRadii({0, 0});  // not every entity: still none
  EXPECT_EQ(weighted.Update(), plain.Update());
  weighted.SetContactRadii({0, 0, 0});
  bool differs = false;
  for (int i = 0; i < 3; ++i) differs |= weighted.Update() != plain.Update();
  EXPECT_TRUE(differs) << "the toy data's onsets count 31x once the sizes are known";
}

// Per-identity averaging over training combinations, where the truth is known: with open
// edges (every message passed unweighted) an episode's hidden states, and so its edge
// probabilities, do not depend on the Gumbel noise, and the same seed builds the same model.
// So a pair's weight over the combinations must be the step-weighted mean of its weights in
// the data sets of the combinations alone, a pair of one combination only must be that
// combination's, and a pair never present together must be 0.
TEST(GnnTrainerTest, CombinationsAverageEachIdentityPairOverTheEpisodesWhereBothArePresent) {
  ToyWorld world({.num_pucks = 2, .steps = 10});
  const std::vector<uint16_t> a_kinds = {0, 1, 2}, b_kinds = {0, 1, 3};
  const rl::EntityLayout layout{3, 4, false};
  GraphDataset all(layout, std::vector<std::vector<uint16_t>>{a_kinds, b_kinds}, 2, 10);
  GraphDataset only_a(layout, a_kinds, 2, 10), only_b(layout, b_kinds, 2, 10);
  // 6 episodes of combination a, 4 of b: unequal counts make the weighting visible
  for (int e = 0; e < 10; ++e) {
    const bool a = e < 6;
    const rl::Episode episode = testing::AsCombination(world.RandomEpisode(e), 4, a ? a_kinds : b_kinds);
    ASSERT_EQ(all.Add(episode), "");
    ASSERT_EQ((a ? only_a : only_b).Add(episode), "");
  }
  for (GraphDataset* d : {&all, &only_a, &only_b}) d->Split(0.34, 1);
  config::GraphConfig config;
  config.hidden_dim = 6;
  config.mlp_hidden = 12;
  config.standardize_inputs = false;  // the same inputs in every data set
  config.eval_chunk_episodes = 3;
  auto evaluate = [&](const GraphDataset& d) {
    GnnTrainer trainer(config, d, 9);
    trainer.model().set_open_edges(true);
    return trainer.Evaluate();
  };
  const EdgeStatistics s = evaluate(all), sa = evaluate(only_a), sb = evaluate(only_b);
  ASSERT_EQ(s.num_entities, 4);
  ASSERT_EQ(s.mean_weight.size(), 16u);
  ASSERT_EQ(sa.num_entities, 3);
  // the model runs in float, on batches of other episodes: sums agree to float precision
  constexpr double kFloat = 1e-6;
  auto w = [](const EdgeStatistics& st, int i, int j) { return st.mean_weight[i * st.num_entities + j]; };
  // arm <-> object 1: in both combinations, 6 : 4 episodes of equal length
  EXPECT_NEAR(w(s, 0, 1), (6 * w(sa, 0, 1) + 4 * w(sb, 0, 1)) / 10, kFloat);
  EXPECT_NEAR(w(s, 1, 0), (6 * w(sa, 1, 0) + 4 * w(sb, 1, 0)) / 10, kFloat);
  // object 2 only in a (its entity 2), object 3 only in b (also its entity 2)
  EXPECT_NEAR(w(s, 0, 2), w(sa, 0, 2), kFloat);
  EXPECT_NEAR(w(s, 1, 2), w(sa, 1, 2), kFloat);
  EXPECT_NEAR(w(s, 0, 3), w(sb, 0, 2), kFloat);
  EXPECT_NEAR(w(s, 3, 1), w(sb, 2, 1), kFloat);
  // objects 2 and 3 never meet: no evidence, no edge
  EXPECT_EQ(w(s, 2, 3), 0.0);
  EXPECT_EQ(w(s, 3, 2), 0.0);
  EXPECT_GT(w(s, 0, 3), 0.0);
  // held-out error per identity: 4 entries, object 3's from b's held-out episodes
  EXPECT_EQ(s.held_out_entity_mse.size(), 4u);
}

}  // namespace
}  // namespace srics::graph_service
