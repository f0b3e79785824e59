#include "common/rl/ground_truth.h"

#include <algorithm>

namespace srics::rl {

InteractionGraph GroundTruthGraph(const config::EnvConfig& env) {
  const auto objects = config::EffectiveObjects(env);
  const int n = 1 + static_cast<int>(objects.size());
  rl::InteractionGraph graph;
  graph.num_entities = n;
  graph.adjacency.assign(static_cast<size_t>(n) * n, 0);
  graph.action_entity = 0;
  // an object no episode holds (outside every object set, e.g. rearrange-4-heldout's object 1)
  // is never moved by anything: no edge into or out of it
  std::vector<bool> appears(n, env.object_sets.empty() && env.eval_object_sets.empty());
  for (const auto* sets : {&env.object_sets, &env.eval_object_sets})
    for (const auto& set : *sets)
      for (int e : set)
        if (e >= 1 && e < n) appears[e] = true;
  const auto movable = [&](int e) { return appears[e] && !objects[e - 1].is_static; };
  for (int i = 1; i < n; ++i)
    if (movable(i)) graph.adjacency[i] = 1;  // arm -> object i
  // a tie acts both ways, but nothing acts on a static object (it is put back every step)
  for (const auto& c : env.connections) {
    if (!appears[c.first] || !appears[c.second]) continue;
    if (movable(c.second)) graph.adjacency[c.first * n + c.second] = 1;
    if (movable(c.first)) graph.adjacency[c.second * n + c.first] = 1;
  }
  return graph;
}

}  // namespace srics::rl
