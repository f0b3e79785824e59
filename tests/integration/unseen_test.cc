// The paper's generalization experiment distributed end to end (slow): the real srics-graph,
// srics-learner and srics-actor processes on the rearrange-4-unseen preset (training on three
// combinations of 3 of Rearrange 4's pucks, evaluation on the fourth) with a LEARNED graph,
// shrunk to a short budget by --set.

#include <gtest/gtest.h>

#include <fstream>

#include "tests/integration/system_harness.h"

namespace srics::testing {
namespace {

// The system test's small settings (tests/integration/system-test.yaml) on the preset.
std::vector<std::string> ShortRun() {
  return {"run.name=unseen-test",
          "run.seed=3",
          "run.total_env_steps=3000",
          "transport.status_period_s=0.5",
          "graph.episodes=60",
          "graph.batch_windows=20",
          "graph.warmup_updates=100",
          "graph.kl_ramp_updates=100",
          "graph.min_updates=200",
          "graph.max_updates=400",
          "graph.eval_every_updates=100",
          "graph.stable_evaluations=2",
          "learner.warmup_steps=500",
          "learner.publish_every_updates=20",
          "learner.checkpoint_every_updates=200",
          "agent.sac.batch_size=64",
          "actors.count=2",
          "actors.eval_every_env_steps=1500",
          "actors.eval_episodes=3"};
}

std::string Text(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

TEST(UnseenCombinationTest, LearnedCatalogueGraphIsAcceptedAndEvaluationRunsOnTheHeldOutCombination) {
  System system("unseen", ShortRun(), "deploy/configs/env/rearrange-4-unseen.yaml");
  ASSERT_FALSE(system.config().graph.ground_truth);
  ASSERT_TRUE(system.config().graph.file.empty());
  system.StartAll(2);
  // the graph service learns from the three training combinations (4 entities per episode)
  // and publishes a graph over the catalogue: the arm and all 4 pucks
  ASSERT_TRUE(system.WaitUntil([&] { return system.graph.has_value(); }, 300s)) << system.Output("graph");
  EXPECT_EQ(system.graph->graph.num_entities, 5);
  EXPECT_EQ(system.graph->structure.depth.size(), 5u);
  EXPECT_EQ(system.graph->graph.action_entity, 0);
  EXPECT_EQ(system.graph->episodes_used, 60u);
  // the run ends by itself
  ASSERT_NO_FATAL_FAILURE(system.ExpectRolesFinish({"learner", "actor-0", "actor-1"}, 400s));
  system.WaitUntil([] { return false; }, 1s);
  // actors and learner accepted the graph: they follow its version and refused nothing
  for (const char* node : {"learner-0", "actor-0", "actor-1"}) {
    ASSERT_TRUE(system.nodes.count(node)) << node;
    EXPECT_EQ(system.nodes[node].report.graph_version, system.graph->version) << node;
    EXPECT_EQ(system.nodes[node].report.dropped, 0u) << node << ": " << system.nodes[node].report.detail;
  }
  for (const char* name : {"learner", "actor-0", "actor-1"})
    EXPECT_EQ(system.Output(name).find("ignored"), std::string::npos) << system.Output(name);
  ASSERT_TRUE(system.stats.has_value());
  EXPECT_GT(system.stats->updates, 0u);
  EXPECT_EQ(system.stats->episodes_rejected, 0u);
  // evaluations (passive, then the policy) ran on the held-out combination: pucks 2, 3, 4
  ASSERT_GE(system.evals.size(), 2u);
  EXPECT_GT(system.evals.back().policy_version, 0u);
  EXPECT_EQ(system.evals.back().summary.entity_distance.size(), 4u);
  const std::string actor0 = Text(system.run_dir() + "/actor-0.out");
  EXPECT_NE(actor0.find("on catalogue entities [0, 2, 3, 4]"), std::string::npos) << actor0.substr(0, 3000);
  EXPECT_EQ(actor0.find("on catalogue entities [0, 1,"), std::string::npos);
}

}  // namespace
}  // namespace srics::testing
