#include "graph_service/dataset.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/graph_service/toy_world.h"

namespace srics::graph_service {
namespace {

using testing::ToyWorld;
using testing::ToyWorldConfig;

GraphDataset ToyData(int episodes, ToyWorldConfig config = {}) {
  ToyWorld world(config);
  GraphDataset data = GraphDataset::ShapedLike(world.RandomEpisode(0));
  for (int e = 0; e < episodes; ++e) EXPECT_EQ(data.Add(world.RandomEpisode(100 + e)), "");
  return data;
}

TEST(GraphDatasetTest, RefusesEpisodesThatDoNotFit) {
  ToyWorld world({});
  const rl::Episode good = world.RandomEpisode(1);
  GraphDataset data = GraphDataset::ShapedLike(good);
  rl::Episode train = good;
  train.mode = rl::EpisodeMode::kTrain;
  EXPECT_EQ(data.Add(train), "not an explore episode");
  rl::Episode nan = good;
  nan.states[7] = std::nanf("");
  EXPECT_NE(data.Add(nan), "");
  rl::Episode shorter = ToyWorld({.steps = 40}).RandomEpisode(1);
  EXPECT_NE(data.Add(shorter), "");
  rl::Episode bigger = ToyWorld({.num_pucks = 3}).RandomEpisode(1);
  EXPECT_NE(data.Add(bigger), "");
  rl::Episode truncated = good;
  truncated.states.resize(truncated.states.size() - 1);
  EXPECT_NE(data.Add(truncated), "");
  EXPECT_EQ(data.size(), 0);
  EXPECT_EQ(data.Add(good), "");
  EXPECT_EQ(data.size(), 1);
}

TEST(GraphDatasetTest, SplitIsDeterministicAndDisjoint) {
  GraphDataset a = ToyData(40), b = ToyData(40);
  a.Split(0.1, 5);
  b.Split(0.1, 5);
  EXPECT_EQ(a.held_out_episodes().size(), 4u);
  EXPECT_EQ(a.train_episodes().size(), 36u);
  EXPECT_EQ(a.held_out_episodes(), b.held_out_episodes());
  for (int h : a.held_out_episodes()) EXPECT_EQ(std::count(a.train_episodes().begin(), a.train_episodes().end(), h), 0);
  b.Split(0.1, 6);
  EXPECT_NE(a.held_out_episodes(), b.held_out_episodes());
  GraphDataset tiny = ToyData(1);
  EXPECT_THROW(tiny.Split(0.1, 1), std::logic_error);
}

TEST(GraphDatasetTest, WindowsHoldPositionsKindsActionsAndChanges) {
  GraphDataset data = ToyData(10);
  data.Split(0.2, 1);
  nn::Rng rng(3);
  WindowBatch<double> batch;
  data.SampleWindows(4, 20, rng, &batch);
  ASSERT_EQ(batch.steps(), 20);
  const int n = data.num_entities();
  ASSERT_EQ(batch.inputs[0].rows(), 4 * n);
  ASSERT_EQ(batch.inputs[0].cols(), 2 + n + 2);
  for (int t = 0; t + 1 < batch.steps(); ++t) {
    for (int r = 0; r < 4 * n; ++r) {
      // consecutive inputs are linked by the targets (teacher forcing)
      EXPECT_NEAR(batch.inputs[t](r, 0) + batch.deltas[t](r, 0), batch.inputs[t + 1](r, 0), 1e-6);
      EXPECT_NEAR(batch.inputs[t](r, 1) + batch.deltas[t](r, 1), batch.inputs[t + 1](r, 1), 1e-6);
      EXPECT_EQ(batch.inputs[t](r, 2 + r % n), 1.0);  // kind one-hot
      // the action is shared by the entities of a window
      EXPECT_EQ(batch.inputs[t](r, 2 + n), batch.inputs[t]((r / n) * n, 2 + n));
    }
  }
}

TEST(ActionEntityTest, PicksTheEntityThatFollowsTheAction) {
  GraphDataset data = ToyData(30, {.num_pucks = 2, .static_pucks = {2}});
  const std::vector<double> c = ActionCorrelations(data);
  EXPECT_GT(c[0], 0.9);
  EXPECT_EQ(c[2], 0.0);  // never moves
  EXPECT_LT(c[1], 0.5);
  EXPECT_EQ(SelectActionEntity(data), 0);
}

TEST(ActionEntityTest, FollowsTheDrivenEntityWhereverItIs) {
  // swap the arm into slot 2: the selection must follow the motion, not the index
  ToyWorld world({.num_pucks = 2});
  rl::Episode first = world.RandomEpisode(0);
  GraphDataset data(first.layout, {2, 1, 0}, 2, first.num_steps);
  for (int e = 0; e < 20; ++e) {
    rl::Episode ep = world.RandomEpisode(10 + e);
    const int d = ep.layout.entity_dim();
    for (int t = 0; t <= ep.num_steps; ++t)
      for (int k = 0; k < d; ++k) std::swap(ep.states[(t * 3 + 0) * d + k], ep.states[(t * 3 + 2) * d + k]);
    ep.entity_kinds = {2, 1, 0};
    ASSERT_EQ(data.Add(ep), "");
  }
  EXPECT_EQ(SelectActionEntity(data), 2);
}

// Training combinations of a catalogue of arm + 3 objects: two pucks per episode.
const std::vector<std::vector<uint16_t>> kCombinations = {{0, 1, 2}, {0, 1, 3}};

TEST(GraphDatasetTest, CombinationsAcceptTheirKindListsOnlyAndIndexTheCatalogue) {
  ToyWorld world({.num_pucks = 2, .steps = 10});
  GraphDataset data({3, 4, false}, kCombinations, 2, 10);
  EXPECT_TRUE(data.combinations());
  EXPECT_EQ(data.graph_entities(), 4);
  EXPECT_EQ(data.graph_kinds(), (std::vector<uint16_t>{0, 1, 2, 3}));
  EXPECT_EQ(data.Add(testing::AsCombination(world.RandomEpisode(1), 4, {0, 1, 2})), "");
  EXPECT_EQ(data.Add(testing::AsCombination(world.RandomEpisode(2), 4, {0, 1, 3})), "");
  // objects 2 and 3 together are not a training combination (the held-out one, say)
  EXPECT_EQ(data.Add(testing::AsCombination(world.RandomEpisode(3), 4, {0, 2, 3})),
            "entity kinds are none of the training object sets");
  EXPECT_EQ(data.size(), 2);
  EXPECT_EQ(data.graph_entity(1, 2), 3);
  EXPECT_EQ(data.graph_entity(0, 2), 2);
  // the kind one-hot of each episode is its own
  WindowBatch<float> batch;
  data.EpisodeBatch({0, 1}, &batch);
  EXPECT_EQ(batch.inputs[0](2, 2 + 2), 1.f);      // episode 0, entity 2: kind 2
  EXPECT_EQ(batch.inputs[0](3 + 2, 2 + 3), 1.f);  // episode 1, entity 2: kind 3
  EXPECT_EQ(batch.inputs[0](3 + 2, 2 + 2), 0.f);
  // the combination of each episode survives a checkpoint
  nn::ByteWriter out;
  data.Save(out);
  GraphDataset loaded({3, 4, false}, kCombinations, 2, 10);
  const std::string bytes = out.Take();
  nn::ByteReader in(bytes, "test");
  loaded.Load(in);
  EXPECT_EQ(loaded.episode_kinds(1), (std::vector<uint16_t>{0, 1, 3}));
  // a repeated kind makes identities ambiguous
  EXPECT_THROW(GraphDataset({3, 4, false}, {{0, 1, 1}, {0, 1, 2}}, 2, 10), std::invalid_argument);
}

TEST(GraphDatasetTest, ActionCorrelationsArePerIdentity) {
  ToyWorld world({.num_pucks = 2, .steps = 10});
  GraphDataset data({3, 4, false}, kCombinations, 2, 10);
  for (int e = 0; e < 20; ++e)
    ASSERT_EQ(data.Add(testing::AsCombination(world.RandomEpisode(e), 4, kCombinations[e % 2])), "");
  const std::vector<double> c = ActionCorrelations(data);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_GT(c[0], 0.9);  // the arm follows the action in every episode
  EXPECT_EQ(SelectActionEntity(data), 0);
}

}  // namespace
}  // namespace srics::graph_service
