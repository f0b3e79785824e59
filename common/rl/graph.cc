#include "common/rl/graph.h"

#include <algorithm>
#include <stdexcept>

namespace srics::rl {
namespace {

// Depth-first enumeration of every simple path from the action node; on reaching a node, all
// nodes on the current path are its ancestors and the path length bounds its depth.
void ExtendPaths(const InteractionGraph& graph, int node, int length, uint64_t on_path,
                 SubgoalStructure* out) {
  out->ancestor_mask[node] |= on_path;
  out->depth[node] = std::max(out->depth[node], length);
  const uint64_t with_node = on_path | (uint64_t{1} << node);
  for (int next = 0; next < graph.num_entities; ++next) {
    if (next == node || !graph.edge(node, next) || ((with_node >> next) & 1u)) continue;
    ExtendPaths(graph, next, length + 1, with_node, out);
  }
}

}  // namespace

InteractionGraph InteractionGraph::Star(int num_entities) {
  InteractionGraph graph;
  graph.num_entities = num_entities;
  graph.adjacency.assign(static_cast<size_t>(num_entities) * num_entities, 0);
  for (int j = 1; j < num_entities; ++j) graph.adjacency[j] = 1;
  graph.action_entity = 0;
  return graph;
}

std::vector<int> SubgoalStructure::SubgoalEntities() const {
  std::vector<int> entities;
  for (int i = 0; i < num_entities(); ++i)
    if (has_subgoal(i)) entities.push_back(i);
  return entities;
}

std::string ValidateGraph(const InteractionGraph& graph) {
  if (graph.num_entities < 1 || graph.num_entities > kMaxGraphEntities)
    return "num_entities " + std::to_string(graph.num_entities) + " outside [1, " +
           std::to_string(kMaxGraphEntities) + "]";
  if (graph.adjacency.size() != static_cast<size_t>(graph.num_entities) * graph.num_entities)
    return "adjacency has " + std::to_string(graph.adjacency.size()) + " entries, expected " +
           std::to_string(graph.num_entities * graph.num_entities);
  if (graph.action_entity < 0 || graph.action_entity >= graph.num_entities)
    return "action_entity " + std::to_string(graph.action_entity) + " is not an entity";
  return "";
}

SubgoalStructure ComputeSubgoalStructure(const InteractionGraph& graph) {
  const std::string problem = ValidateGraph(graph);
  if (!problem.empty()) throw std::invalid_argument("interaction graph: " + problem);
  SubgoalStructure out;
  out.ancestor_mask.assign(graph.num_entities, 0);
  out.depth.assign(graph.num_entities, -1);
  // the action node is not an entity: the path starts at the driven entity with length 1
  ExtendPaths(graph, graph.action_entity, 1, 0, &out);
  return out;
}

std::string DescribeGraph(const InteractionGraph& graph) {
  std::string text = "action->" + std::to_string(graph.action_entity);
  for (int i = 0; i < graph.num_entities; ++i)
    for (int j = 0; j < graph.num_entities; ++j)
      if (i != j && graph.edge(i, j)) text += ", " + std::to_string(i) + "->" + std::to_string(j);
  return text;
}

std::string GraphMismatch(const InteractionGraph& graph, int num_entities) {
  if (graph.num_entities == num_entities) return "";
  return "the graph has " + std::to_string(graph.num_entities) + " entities, this run's environment " +
         std::to_string(num_entities);
}

}  // namespace srics::rl
