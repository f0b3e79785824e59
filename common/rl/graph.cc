#include "common/rl/graph.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

namespace srics::rl {
namespace {

// Every simple path from the driven entity, as the set of its nodes and its last node:
// reach[S] has bit v when some simple path visits exactly the entities of S and ends at v. The
// sets are visited in increasing order (adding a node only makes a set larger), so each is
// complete before it is extended: O(2^N * N) bit operations, about a million for N = 16,
// whatever the edges (enumerating the paths themselves grows like N! on a dense graph).
void SimplePathSets(const InteractionGraph& graph, SubgoalStructure* out) {
  const int n = graph.num_entities;
  std::vector<uint32_t> successors(n, 0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j && graph.edge(i, j)) successors[i] |= uint32_t{1} << j;
  std::vector<uint32_t> reach(size_t{1} << n, 0);
  reach[uint32_t{1} << graph.action_entity] = uint32_t{1} << graph.action_entity;
  for (uint32_t set = 1; set < reach.size(); ++set) {
    for (uint32_t ends = reach[set]; ends != 0; ends &= ends - 1) {
      const int last = std::countr_zero(ends);
      // a path through `set` ending at `last`: every other node of it is an ancestor of `last`;
      // its length in edges, counting the action node's edge, is the number of its nodes
      out->ancestor_mask[last] |= set & ~(uint32_t{1} << last);
      out->depth[last] = std::max(out->depth[last], std::popcount(set));
      for (uint32_t next = successors[last] & ~set; next != 0; next &= next - 1) {
        const uint32_t bit = next & (~next + 1);
        reach[set | bit] |= bit;
      }
    }
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
  for (int i = 0; i < num_entities(); ++i) {
    const int p = partner_of(i);
    if (has_subgoal(i) && (p < 0 || p > i)) entities.push_back(i);
  }
  return entities;
}

uint64_t SubgoalStructure::AncestorsOf(const SubgoalUnit& unit) const {
  uint64_t mask = 0;
  for (int k = 0; k < unit.size(); ++k) {
    const int e = unit.member(k);
    if (e < num_entities()) mask |= ancestor_mask[e];
  }
  return mask & ~unit.bits();
}

void PairMutualAncestors(SubgoalStructure* s, int driven) {
  const int n = s->num_entities();
  std::vector<int> mutual(n, -1), count(n, 0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (i == j || i == driven || j == driven || !s->has_subgoal(i) || !s->has_subgoal(j)) continue;
      if (s->is_ancestor(i, j) && s->is_ancestor(j, i)) {
        mutual[i] = j;
        ++count[i];
      }
    }
  }
  s->partner.assign(n, -1);
  for (int i = 0; i < n; ++i)
    if (count[i] == 1 && count[mutual[i]] == 1) s->partner[i] = mutual[i];
}

std::string ValidateGraph(const InteractionGraph& graph) {
  if (graph.num_entities < 1 || graph.num_entities > kMaxGraphEntities)
    return "num_entities " + std::to_string(graph.num_entities) + " outside [1, " + std::to_string(kMaxGraphEntities) +
           "]";
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
  // the action node is not an entity: a path starts at the driven entity with length 1
  SimplePathSets(graph, &out);
  return out;
}

SubgoalStructure EpisodeSubgoalStructure(const InteractionGraph& catalogue, std::span<const uint16_t> kinds) {
  const std::string problem = ValidateGraph(catalogue);
  if (!problem.empty()) throw std::invalid_argument("interaction graph: " + problem);
  const int n = static_cast<int>(kinds.size());
  std::vector<int> position(catalogue.num_entities, -1);
  for (int e = 0; e < n; ++e) {
    if (kinds[e] >= catalogue.num_entities)
      throw std::invalid_argument("entity kind " + std::to_string(kinds[e]) + " is not in the " +
                                  std::to_string(catalogue.num_entities) + "-entity graph");
    if (position[kinds[e]] >= 0)
      throw std::invalid_argument("entity kind " + std::to_string(kinds[e]) + " is present twice");
    position[kinds[e]] = e;
  }
  SubgoalStructure out;
  out.ancestor_mask.assign(n, 0);
  out.depth.assign(n, -1);
  const int driven = position[catalogue.action_entity];
  if (driven < 0) return out;  // nothing the action moves is here
  // the catalogue graph induced on the present entities, in the episode's indices
  InteractionGraph present;
  present.num_entities = n;
  present.action_entity = driven;
  present.adjacency.assign(static_cast<size_t>(n) * n, 0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) present.adjacency[i * n + j] = i != j && catalogue.edge(kinds[i], kinds[j]) ? 1 : 0;
  return ComputeSubgoalStructure(present);
}

SubgoalStructure CatalogueSubgoals::For(std::span<const uint16_t> kinds) const {
  if (graph) {
    SubgoalStructure structure = EpisodeSubgoalStructure(*graph, kinds);
    if (joint_ties) {
      int driven = -1;
      for (size_t e = 0; e < kinds.size(); ++e)
        if (kinds[e] == graph->action_entity) driven = static_cast<int>(e);
      PairMutualAncestors(&structure, driven);
    }
    return structure;
  }
  SubgoalStructure all;
  all.ancestor_mask.assign(kinds.size(), 0);
  all.depth.assign(kinds.size(), 1);
  return all;
}

SubgoalStructure CatalogueSubgoals::For(std::span<const int> kinds) const {
  std::vector<uint16_t> k;
  for (int kind : kinds) {
    if (kind < 0 || kind > 0xffff) throw std::invalid_argument("entity kind " + std::to_string(kind) + " out of range");
    k.push_back(static_cast<uint16_t>(kind));
  }
  return For(std::span<const uint16_t>(k));
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
