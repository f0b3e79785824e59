#include "common/rl/ground_truth.h"

namespace srics::rl {

InteractionGraph GroundTruthGraph(const config::EnvConfig& env) {
  const auto objects = config::EffectiveObjects(env);
  const int n = 1 + static_cast<int>(objects.size());
  rl::InteractionGraph graph;
  graph.num_entities = n;
  graph.adjacency.assign(static_cast<size_t>(n) * n, 0);
  graph.action_entity = 0;
  for (int i = 1; i < n; ++i)
    if (!objects[i - 1].is_static) graph.adjacency[i] = 1;  // arm -> object i
  // a tie acts both ways, but nothing acts on a static object (it is put back every step)
  for (const auto& c : env.connections) {
    if (!objects[c.second - 1].is_static) graph.adjacency[c.first * n + c.second] = 1;
    if (!objects[c.first - 1].is_static) graph.adjacency[c.second * n + c.first] = 1;
  }
  return graph;
}

}  // namespace srics::rl
