// Learning the graph of a small toy world end to end (slow). DISABLED: with the training
// budget that fits the suite, the model does not yet learn the pushes of the free puck (its
// held-out error stays at the no-motion baseline), so the arm -> puck edge is not recovered;
// see graph_service/README.md, "Status". Run it with --gtest_also_run_disabled_tests.
#include <gtest/gtest.h>

#include <atomic>

#include "tests/graph_service/toy_world.h"

namespace srics::graph {
namespace {

TEST(GraphLearningTest, DISABLED_RecoversArmFreePuckStaticPuck) {
  config::GraphConfig c;
  c.episodes = 1000;
  c.max_updates = 4000;
  c.min_updates = 3000;
  c.eval_every_updates = 500;
  c.stable_evaluations = 2;
  testing::ToySource source({.num_pucks = 2, .static_pucks = {2}}, c.episodes, 1);
  testing::RecordingSink sink;
  GraphService service(c, {.seed = 1}, &source, &sink, {});
  std::atomic<bool> stop{false};
  ASSERT_EQ(service.Run(stop), 0);
  ASSERT_EQ(sink.graphs.size(), 1u);
  // the arm drives puck 1; nothing acts on the static puck 2; nothing acts on the arm
  EXPECT_EQ(rl::DescribeGraph(sink.graphs[0].graph), "action->0, 0->1");
}

}  // namespace
}  // namespace srics::graph
