// Graph refinement (graph.refine_after_publish) on the toy world (slow): a rope too long for
// random actions to pull taut is missing from the first graph; training episodes that kick one
// roped puck away from the other bring it in as graph version 2. (The mechanics, on a tiny
// model: service_test.cc.)
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <string>
#include <vector>

#include "common/rl/graph.h"
#include "graph_service/learned_graph.h"
#include "graph_service/service.h"
#include "tests/graph_service/toy_world.h"

namespace srics::graph_service {
namespace {

using testing::FeedSource;
using testing::RecordingSink;
using testing::ToyWorld;

constexpr int kSteps = 20;

// Two pucks on a 0.3 m rope; pucks slide on after a push (the rope drags the other one while
// the arm is already away, so only the rope explains its motion)
testing::ToyWorldConfig RopedPucks() {
  return {.num_pucks = 2, .ropes = {{1, 2}}, .rope_length = 0.3, .slide = 0.8, .steps = kSteps};
}

// A small model that learns the toy world in ~2000 updates (a few seconds).
config::GraphConfig RefiningConfig() {
  config::GraphConfig c;
  c.episodes = 200;
  c.episode_steps = kSteps;
  c.window = 10;
  c.batch_windows = 32;
  c.hidden_dim = 8;
  c.mlp_hidden = 32;
  c.warmup_updates = 300;
  c.kl_ramp_updates = 200;
  c.max_updates = 1500;
  c.min_updates = 1500;
  c.eval_every_updates = 100;
  c.stable_evaluations = 2;
  c.refine_after_publish = true;
  c.refine_updates_per_episode = 5;
  return c;
}

ServiceOptions Options(ToyWorld& world, const std::string& dir, uint64_t seed) {
  const rl::Episode e = world.RandomEpisode(0);
  ServiceOptions o{.state_dir = dir, .seed = seed, .render_pictures = false};
  o.shape = DatasetShape{e.layout, e.entity_kinds, e.action_dim};
  o.refine_episode_steps = kSteps;
  return o;
}

std::string FreshDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

// Measured on the AVX-512 EPYC (seeds 1-8, 600 kicks at most): the first graph is
// "action->0, 0->1, 0->2" for all 8; refinement publishes exactly the rope both ways for 6 of 8,
// after 300-320 training episodes (the ring of 180 fills, then a new warm-up and KL ramp);
// seeds 2 and 7 publish nothing new. Without the new warm-up (a closed gate is sampled open
// about edge_prior of the time) 2-4 of 5 found it, some after 1000 episodes. So: at least 2 of
// seeds 1-4.
TEST(GraphRefinementTest, TrainingEpisodesBringInTheRopeRandomActionsMissed) {
  const std::string rope = "action->0, 0->1, 0->2, 1->2, 2->1";
  int found = 0;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const std::string dir = FreshDir("graph_refinement_" + std::to_string(seed));
    ToyWorld world(RopedPucks());
    FeedSource source;
    for (int i = 0; i < 200; ++i) source.queue.push_back(world.RandomEpisode(1000 + i));
    RecordingSink sink;
    GraphService service(RefiningConfig(), Options(world, dir, seed), &source, &sink, {});
    std::atomic<bool> stop{false};
    ASSERT_EQ(service.Run(stop), 0);
    ASSERT_EQ(sink.graphs.size(), 1u);
    // random actions never showed the rope
    EXPECT_EQ(rl::DescribeGraph(sink.graphs[0].graph), "action->0, 0->1, 0->2") << "seed " << seed;
    EXPECT_TRUE(service.progress().refining);
    for (int i = 0; i < 600 && sink.graphs.size() < 2; ++i) {
      // the policy kicks either puck away from the other
      source.queue.push_back(world.PushEpisode(5000 + i, i % 2 ? 1 : 2, i % 2 ? 2 : 1, 0.27, 6));
      service.Step();
      service.Step();
    }
    EXPECT_EQ(service.progress().dropped, 0);
    if (sink.graphs.size() < 2) continue;
    ASSERT_EQ(sink.graphs.size(), 2u) << "one publication per change";
    const rl::GraphUpdate& v2 = sink.graphs[1];
    EXPECT_EQ(v2.version, 2u);
    EXPECT_GT(v2.training_updates, sink.graphs[0].training_updates);
    // the saved graph is the new version: a restart re-publishes it
    EXPECT_EQ(LoadGraph(dir + "/graph.json").version, 2u);
    EXPECT_GE(service.progress().refine_episodes, 180) << "not before the ring of training episodes is full";
    if (rl::DescribeGraph(v2.graph) == rope)
      ++found;
    else
      ADD_FAILURE() << "seed " << seed << " published " << rl::DescribeGraph(v2.graph);
  }
  EXPECT_GE(found, 2) << "seeds 1-4 whose refinement found exactly the rope";
}

}  // namespace
}  // namespace srics::graph_service
