#pragma once
// Interaction graphs over entities and the independently controllable subgoals they imply
// (docs/method.md sections 2-3). Shared by the graph service (which learns the graph) and
// by actors and the learner (which use it); no DDS, no YAML.

#include <cstdint>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace srics::rl {

// A directed graph over N entities plus an action node that drives one entity.
// adjacency[i * N + j] != 0 means "entity i acts on entity j".
struct InteractionGraph {
  int num_entities = 0;
  std::vector<uint8_t> adjacency;
  int action_entity = 0;  // the entity the action node has an edge to (the arm)

  bool edge(int from, int to) const { return adjacency[from * num_entities + to] != 0; }
  // The graph in which the action drives the arm and the arm acts on every other entity
  // (what the graph service finds on plain Rearrange); handy for tests and ground truth.
  static InteractionGraph Star(int num_entities);
  bool operator==(const InteractionGraph&) const = default;
};

// One subgoal: an entity, or (graph.object_ties: joint) a tied pair attempted as one, both
// objects' goals at once, solved when both are. An entity converts to the unit of itself alone.
struct SubgoalUnit {
  int entity = -1;
  int partner = -1;  // the pair's other object; -1: the entity alone

  SubgoalUnit() = default;
  SubgoalUnit(int entity, int partner = -1) : entity(entity), partner(partner) {}  // NOLINT(runtime/explicit)
  int size() const { return partner >= 0 ? 2 : 1; }
  int member(int k) const { return k == 0 ? entity : partner; }  // k < size()
  bool contains(int j) const { return j == entity || (partner >= 0 && j == partner); }
  // bit e set for each member e
  uint64_t bits() const { return (uint64_t{1} << entity) | (partner >= 0 ? uint64_t{1} << partner : 0); }
};

// Ancestor sets and depths derived from a graph.
struct SubgoalStructure {
  // bit j of ancestor_mask[i]: entity j lies on some simple path from the action node to i
  // (i itself excluded).
  std::vector<uint64_t> ancestor_mask;
  // length (in edges) of the longest simple path from the action node to i; the driven entity
  // has depth 1; -1 when no path exists (no subgoal for that entity).
  std::vector<int> depth;

  // graph.object_ties: joint: partner[i] is the object attempted together with i (the two are
  // each other's ancestors), -1 for none; empty: every subgoal is one entity
  std::vector<int> partner;

  int num_entities() const { return static_cast<int>(depth.size()); }
  bool has_subgoal(int entity) const { return depth[entity] >= 1; }
  bool is_ancestor(int ancestor, int of) const { return (ancestor_mask[of] >> ancestor) & 1u; }
  int partner_of(int entity) const { return entity < static_cast<int>(partner.size()) ? partner[entity] : -1; }
  // the subgoal `entity` belongs to (alone, or with its partner)
  SubgoalUnit UnitOf(int entity) const { return {entity, partner_of(entity)}; }
  // the ancestors of the unit's entities outside the unit: what its selectivity leaves alone
  uint64_t AncestorsOf(const SubgoalUnit& unit) const;
  // the entities that have a subgoal, in index order; a pair appears once, by its lower entity
  std::vector<int> SubgoalEntities() const;
  bool operator==(const SubgoalStructure&) const = default;
};

// Pairs the objects that are each other's ancestors (a tie read both ways) into one subgoal
// each: sets structure->partner. `driven` (the arm) is never paired, and an object with more
// than one such partner (a cycle of three or more) stays a subgoal of its own.
void PairMutualAncestors(SubgoalStructure* structure, int driven);

// Largest graph the exact simple-path search accepts: it walks the sets of nodes a simple path
// can visit (2^N sets), so the work is bounded by the entity count, never by the edges.
constexpr int kMaxGraphEntities = 16;

// Ancestor sets over all simple paths from the action node and longest-simple-path depths.
// Handles cycles. Throws std::invalid_argument for a malformed graph (size mismatch, action
// entity out of range, more than kMaxGraphEntities entities), checked before any search.
// At most ~2^N * N steps: a complete graph of 16 entities takes milliseconds.
SubgoalStructure ComputeSubgoalStructure(const InteractionGraph& graph);

// The subgoal structure of one episode from the run's catalogue graph (the arm and every object
// of the environment config): entity e of the episode is catalogue entity kinds[e] (its
// Episode::entity_kinds). The graph is restricted to the present entities before the search,
// since an absent object passes nothing on: a path through it does not exist in this episode.
// With every entity present (kinds = 0..N-1) it equals ComputeSubgoalStructure(catalogue).
// Without the action entity present no entity has a subgoal. Throws std::invalid_argument for
// a malformed graph, a kind outside it or a kind present twice.
SubgoalStructure EpisodeSubgoalStructure(const InteractionGraph& catalogue, std::span<const uint16_t> kinds);

// What actors and the learner act on: the catalogue graph (methods that use one), from which
// every episode's structure is derived, or none (every present entity is a subgoal with no
// ancestors: SMORL, SAC+HER, HAC).
struct CatalogueSubgoals {
  std::optional<InteractionGraph> graph;
  bool joint_ties = false;  // graph.object_ties: joint: pairs from PairMutualAncestors
  SubgoalStructure For(std::span<const uint16_t> kinds) const;
  SubgoalStructure For(std::span<const int> kinds) const;
};

// Validates a graph; returns an empty string when fine, else what is wrong.
std::string ValidateGraph(const InteractionGraph& graph);

// Whether a received graph can be used by a process whose environment has `num_entities`
// entities: empty when it fits, else why not. Actors, the learner and the in-process run all
// decide with this one check.
std::string GraphMismatch(const InteractionGraph& graph, int num_entities);

// One-line description such as "action->0, 0->1, 0->2, 2->3" for logs and monitors.
std::string DescribeGraph(const InteractionGraph& graph);

}  // namespace srics::rl
