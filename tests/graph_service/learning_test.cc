// Learning the graph of a small real environment end to end (slow): the MuJoCo arm, one free
// puck and one static puck, random-action episodes from actor::RunExploreEpisode, the
// service with the default GraphConfig except a smaller data set and update budget.
// With the defaults of 2026-12-03 (onset weight, object pairs apart, KL ramp 1500; 4000 updates)
// each test took 290-450 s of wall time with four jobs on the two cores of the AVX-512 EPYC.
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <vector>

#include "actor/env/random_table.h"
#include "actor/env/rearrange_env.h"
#include "actor/explore_episode.h"
#include "common/config/config.h"
#include "common/config/env_config.h"
#include "common/config/graph_config.h"
#include "common/rl/agent_shape.h"
#include "common/rl/ground_truth.h"
#include "graph_service/service.h"
#include "tests/graph_service/toy_world.h"

namespace srics::graph_service {
namespace {

// Explore episodes straight from the environment (episode i is reset with seed base + i).
class EnvSource : public EpisodeSource {
 public:
  EnvSource(const config::EnvConfig& env, int episodes, int steps, uint64_t seed)
      : env_(env::MakeRearrangeEnv(env)), left_(episodes), steps_(steps), seed_(seed), rng_(seed) {}
  bool Poll(std::chrono::milliseconds, std::vector<rl::Episode>* out) override {
    for (int i = 0; i < 50 && left_ > 0; ++i) {
      auto episode = actor::RunExploreEpisode(*env_, steps_, seed_ * 1000003 + next_++, rng_);
      if (episode) {
        out->push_back(std::move(*episode));
        --left_;
      }
    }
    return left_ > 0 || !out->empty();
  }

 private:
  std::unique_ptr<env::Environment> env_;
  int left_, steps_;
  uint64_t seed_, next_ = 0;
  nn::Rng rng_;
};

using testing::RecordingSink;

// The options the role programs give the service for this environment (shape, limits, the
// entities' footprints), with this seed and no pictures.
ServiceOptions RunOptions(const config::EnvConfig& env, uint64_t seed) {
  config::Config config;
  config.env = env;
  ServiceOptions options = ServiceOptionsFor(config, rl::RunShapeFor(config), "");
  options.seed = seed;
  options.render_pictures = false;
  return options;
}

// The default GraphConfig with the smaller data set and update budget of these tests: 1000
// updates at the full KL weight after the warm-up (1500) and the KL ramp (1500).
config::GraphConfig SmallBudget() {
  config::GraphConfig c;
  c.episodes = 600;
  c.max_updates = c.warmup_updates + c.kl_ramp_updates + 1000;
  c.min_updates = c.max_updates;
  c.eval_every_updates = 1000;
  return c;
}

// What one run of the service published, how it ended and what it dropped.
struct Learned {
  int exit_code = -1;
  std::vector<rl::GraphUpdate> graphs;
  int dropped = 0;
};

// Runs the service with config c over explore episodes of env (source seeded with
// source_seed) until it publishes a graph or the episodes run out.
Learned LearnGraph(const config::EnvConfig& env, const config::GraphConfig& c, const ServiceOptions& options,
                   uint64_t source_seed) {
  EnvSource source(env, c.episodes, c.episode_steps, source_seed);
  RecordingSink sink;
  GraphService service(c, options, &source, &sink, {});
  std::atomic<bool> stop{false};
  Learned learned;
  learned.exit_code = service.Run(stop);
  learned.graphs = sink.graphs;
  learned.dropped = service.progress().dropped;
  return learned;
}

TEST(GraphLearningTest, RecoversArmFreePuckStaticPuck) {
  config::EnvConfig env;
  env.objects.resize(2);
  env.objects[1].is_static = true;  // entity 2
  const Learned learned = LearnGraph(env, SmallBudget(), RunOptions(env, 1), 7);
  ASSERT_EQ(learned.exit_code, 0);
  ASSERT_EQ(learned.graphs.size(), 1u);
  const rl::GraphUpdate& g = learned.graphs[0];
  // the arm drives puck 1; nothing acts on the static puck 2; nothing acts on the arm
  EXPECT_EQ(rl::DescribeGraph(g.graph), "action->0, 0->1");
  EXPECT_EQ(g.graph.action_entity, 0);
}

// The generalization setting with a known truth: three objects, object 3 static, every
// training episode presents two of them ({1,2}, {1,3}, {2,3}). One model learns from all
// combinations and the graph over the catalogue must have the arm driving the two free
// objects and nothing into the static one or the arm: each arm -> object weight is averaged
// over the two combinations holding that object, object -> object pairs over the one that
// holds both. Measured (seed 1, 3000 updates, 348 s under load 6): "action->0, 0->1, 0->2,
// 1->2": the free pucks' contact edge 1 -> 2 is kept as well (real contacts; in the paper's
// 4-puck tables the defaults close such edges, here the pair's weight comes from a third of
// the data). So the test checks the edges the truth is certain about.
TEST(GraphLearningTest, RecoversTheCatalogueGraphFromCombinationsOfTwoOfThreeObjects) {
  config::EnvConfig env;
  env.objects.resize(3);
  env.objects[2].is_static = true;  // entity 3
  env.object_sets = {{1, 2}, {1, 3}, {2, 3}};
  const ServiceOptions options = RunOptions(env, 1);
  ASSERT_EQ(options.shape->episode_kinds.size(), 3u);
  const Learned learned = LearnGraph(env, SmallBudget(), options, 7);
  ASSERT_EQ(learned.exit_code, 0);
  EXPECT_EQ(learned.dropped, 0);
  ASSERT_EQ(learned.graphs.size(), 1u);
  const rl::GraphUpdate& g = learned.graphs[0];
  ASSERT_EQ(g.graph.num_entities, 4);
  SCOPED_TRACE(rl::DescribeGraph(g.graph));
  EXPECT_EQ(g.graph.action_entity, 0);
  EXPECT_TRUE(g.graph.edge(0, 1));
  EXPECT_TRUE(g.graph.edge(0, 2));
  for (int i = 0; i < 4; ++i) {
    EXPECT_FALSE(g.graph.edge(i, 3)) << i << " -> the static object";
    EXPECT_FALSE(g.graph.edge(i, 0)) << i << " -> the arm";
  }
  // the static object has no subgoal, the free ones have the arm as ancestor
  EXPECT_EQ(g.structure.depth[3], -1);
  EXPECT_TRUE(g.structure.is_ancestor(0, 1));
  EXPECT_TRUE(g.structure.is_ancestor(0, 2));
}

// A generated table that was not used while choosing the settings (random table 1001: a
// static cylinder, two free cylinders of other sizes and masses tied by a 14.5 cm rope), with
// the default settings (the paper's mean weight read-out, object pairs both ways, nothing into
// or out of a static object): the exact graph by construction, arm -> both free objects and
// the rope both ways, nothing into the static one.
TEST(GraphLearningTest, RecoversTheGraphOfAGeneratedTable) {
  const config::EnvConfig env = env::RandomTable(1001);
  const std::string expected = rl::DescribeGraph(rl::GroundTruthGraph(env));
  ASSERT_EQ(expected, "action->0, 0->2, 0->3, 2->3, 3->2");
  const Learned learned = LearnGraph(env, SmallBudget(), RunOptions(env, 2), 11);
  ASSERT_EQ(learned.exit_code, 0);
  ASSERT_EQ(learned.graphs.size(), 1u);
  EXPECT_EQ(rl::DescribeGraph(learned.graphs[0].graph), expected);
}

}  // namespace
}  // namespace srics::graph_service
