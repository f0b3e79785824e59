#include "common/rl/graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <random>

namespace srics::rl {
namespace {

InteractionGraph FromEdges(int n, std::vector<std::pair<int, int>> edges, int action = 0) {
  InteractionGraph graph;
  graph.num_entities = n;
  graph.adjacency.assign(n * n, 0);
  for (auto [from, to] : edges) graph.adjacency[from * n + to] = 1;
  graph.action_entity = action;
  return graph;
}

uint64_t Mask(std::initializer_list<int> entities) {
  uint64_t mask = 0;
  for (int e : entities) mask |= uint64_t{1} << e;
  return mask;
}

TEST(GraphTest, StarGivesArmDepthOneAndPucksDepthTwo) {
  SubgoalStructure s = ComputeSubgoalStructure(InteractionGraph::Star(4));
  EXPECT_EQ(s.depth, (std::vector<int>{1, 2, 2, 2}));
  EXPECT_EQ(s.ancestor_mask[0], 0u);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(s.ancestor_mask[i], Mask({0})) << i;
  EXPECT_EQ(s.SubgoalEntities(), (std::vector<int>{0, 1, 2, 3}));
}

TEST(GraphTest, RelationalGraphWithCycleAndStaticPuck) {
  // arm 0 -> pucks 2, 3, 4; tied pair 2 <-> 3 (a cycle); static puck 1 unreachable
  auto graph = FromEdges(5, {{0, 2}, {0, 3}, {0, 4}, {2, 3}, {3, 2}});
  SubgoalStructure s = ComputeSubgoalStructure(graph);
  // longest simple paths: action->0->2->3 has 3 edges, likewise 3 via 2
  EXPECT_EQ(s.depth, (std::vector<int>{1, -1, 3, 3, 2}));
  EXPECT_FALSE(s.has_subgoal(1));
  EXPECT_EQ(s.ancestor_mask[1], 0u);
  EXPECT_EQ(s.ancestor_mask[2], Mask({0, 3}));
  EXPECT_EQ(s.ancestor_mask[3], Mask({0, 2}));
  EXPECT_EQ(s.ancestor_mask[4], Mask({0}));
  EXPECT_EQ(s.SubgoalEntities(), (std::vector<int>{0, 2, 3, 4}));
}

// graph.object_ties: joint: the tied pucks 2 <-> 3 (each the other's ancestor) become one
// subgoal, listed once by puck 2; their ancestors outside the pair are the arm's.
TEST(JointTiesTest, MutualAncestorsArePairedAndListedOnce) {
  SubgoalStructure s = ComputeSubgoalStructure(FromEdges(5, {{0, 2}, {0, 3}, {0, 4}, {2, 3}, {3, 2}}));
  EXPECT_EQ(s.UnitOf(2).size(), 1) << "no pairs before PairMutualAncestors";
  PairMutualAncestors(&s, 0);
  EXPECT_EQ(s.partner, (std::vector<int>{-1, -1, 3, 2, -1}));
  EXPECT_EQ(s.SubgoalEntities(), (std::vector<int>{0, 2, 4}));
  const SubgoalUnit pair = s.UnitOf(2);
  EXPECT_EQ(pair.size(), 2);
  EXPECT_EQ(pair.member(1), 3);
  EXPECT_TRUE(pair.contains(3) && pair.contains(2) && !pair.contains(0));
  EXPECT_EQ(s.UnitOf(3).member(1), 2);
  EXPECT_EQ(s.AncestorsOf(pair), Mask({0}));
  EXPECT_EQ(s.AncestorsOf(SubgoalUnit(2)), Mask({0, 3})) << "alone, its partner is an ancestor";
  EXPECT_EQ(s.AncestorsOf(SubgoalUnit(4)), Mask({0}));
}

TEST(JointTiesTest, AChainOfTiesAndTheArmAreNeverPaired) {
  // 2 <-> 3 <-> 4: puck 3 has two mutual partners, so none of the three is paired
  SubgoalStructure chain = ComputeSubgoalStructure(FromEdges(5, {{0, 2}, {2, 3}, {3, 2}, {3, 4}, {4, 3}}));
  PairMutualAncestors(&chain, 0);
  EXPECT_EQ(chain.partner, (std::vector<int>(5, -1)));
  EXPECT_EQ(chain.SubgoalEntities(), (std::vector<int>{0, 2, 3, 4}));
  // an object that acts back on the arm is still not its ancestor (every path starts at the
  // arm): the arm is never paired
  SubgoalStructure back = ComputeSubgoalStructure(FromEdges(3, {{0, 1}, {1, 0}, {0, 2}}));
  PairMutualAncestors(&back, 0);
  EXPECT_EQ(back.partner, (std::vector<int>(3, -1)));
}

TEST(JointTiesTest, TheCataloguePairsInEachEpisodesIndices) {
  CatalogueSubgoals subgoals{FromEdges(5, {{0, 2}, {0, 3}, {0, 4}, {2, 3}, {3, 2}}), true};
  // every object present: catalogue indices
  EXPECT_EQ(subgoals.For(std::vector<int>{0, 1, 2, 3, 4}).partner, (std::vector<int>{-1, -1, 3, 2, -1}));
  // objects 1 and 4 absent: the pucks 2, 3 are the episode's entities 1, 2
  EXPECT_EQ(subgoals.For(std::vector<int>{0, 2, 3}).partner, (std::vector<int>{-1, 2, 1}));
  // one of the pair absent: no pair
  EXPECT_EQ(subgoals.For(std::vector<int>{0, 2, 4}).partner, (std::vector<int>{-1, -1, -1}));
  subgoals.joint_ties = false;
  EXPECT_TRUE(subgoals.For(std::vector<int>{0, 1, 2, 3, 4}).partner.empty());
}

TEST(GraphTest, ChainAndDiamondTakeLongestPathAndEveryPathNode) {
  // 0 -> 1 -> 2 -> 3 and a shortcut 0 -> 3; plus 1 -> 4, 0 -> 4
  auto graph = FromEdges(5, {{0, 1}, {1, 2}, {2, 3}, {0, 3}, {1, 4}, {0, 4}});
  SubgoalStructure s = ComputeSubgoalStructure(graph);
  EXPECT_EQ(s.depth, (std::vector<int>{1, 2, 3, 4, 3}));
  EXPECT_EQ(s.ancestor_mask[3], Mask({0, 1, 2}));
  EXPECT_EQ(s.ancestor_mask[4], Mask({0, 1}));
}

TEST(GraphTest, CycleBackToTheArmDoesNotMakeItItsOwnAncestor) {
  auto graph = FromEdges(3, {{0, 1}, {1, 0}, {1, 2}});
  SubgoalStructure s = ComputeSubgoalStructure(graph);
  EXPECT_EQ(s.ancestor_mask[0], 0u);
  EXPECT_EQ(s.depth, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(s.ancestor_mask[2], Mask({0, 1}));
}

TEST(GraphTest, ActionOnAnotherEntity) {
  auto graph = FromEdges(3, {{2, 0}}, /*action=*/2);
  SubgoalStructure s = ComputeSubgoalStructure(graph);
  EXPECT_EQ(s.depth, (std::vector<int>{2, -1, 1}));
  EXPECT_EQ(s.ancestor_mask[0], Mask({2}));
}

TEST(GraphTest, MalformedGraphsAreRejectedWithTheReason) {
  InteractionGraph graph = InteractionGraph::Star(3);
  graph.adjacency.pop_back();
  EXPECT_THROW(
      {
        try {
          ComputeSubgoalStructure(graph);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("adjacency has 8 entries, expected 9"), std::string::npos);
          throw;
        }
      },
      std::invalid_argument);
  graph = InteractionGraph::Star(3);
  graph.action_entity = 3;
  EXPECT_NE(ValidateGraph(graph).find("action_entity 3"), std::string::npos);
  EXPECT_EQ(ValidateGraph(InteractionGraph::Star(3)), "");
}

// The definition, by brute force: every simple path from the driven entity, depth first.
void ReferencePaths(const InteractionGraph& g, int node, int length, uint64_t on_path, SubgoalStructure* out) {
  out->ancestor_mask[node] |= on_path;
  out->depth[node] = std::max(out->depth[node], length);
  const uint64_t with_node = on_path | (uint64_t{1} << node);
  for (int next = 0; next < g.num_entities; ++next)
    if (next != node && g.edge(node, next) && !((with_node >> next) & 1u))
      ReferencePaths(g, next, length + 1, with_node, out);
}

TEST(GraphTest, AncestorsAndDepthsMatchEveryPathEnumeratedOnRandomGraphs) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 1 + trial % 8;
    InteractionGraph g;
    g.num_entities = n;
    g.action_entity = static_cast<int>(rng() % n);
    const double density = (trial % 5 + 1) / 5.0;
    for (int i = 0; i < n * n; ++i) g.adjacency.push_back(std::uniform_real_distribution<>(0, 1)(rng) < density);
    SubgoalStructure want;
    want.ancestor_mask.assign(n, 0);
    want.depth.assign(n, -1);
    ReferencePaths(g, g.action_entity, 1, 0, &want);
    const SubgoalStructure got = ComputeSubgoalStructure(g);
    EXPECT_EQ(got.ancestor_mask, want.ancestor_mask) << DescribeGraph(g);
    EXPECT_EQ(got.depth, want.depth) << DescribeGraph(g);
  }
}

// Issue 15: every edge of 16 entities set (a sample anyone on the domain can publish) made the
// path enumeration run for ~15! paths; the work is now bounded by 2^N whatever the edges.
TEST(GraphTest, CompleteGraphOfTheLargestSizeIsQuick) {
  InteractionGraph g;
  g.num_entities = kMaxGraphEntities;
  g.adjacency.assign(kMaxGraphEntities * kMaxGraphEntities, 1);
  const auto start = std::chrono::steady_clock::now();
  const SubgoalStructure s = ComputeSubgoalStructure(g);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 2.0);  // milliseconds in practice; the old search did not end in hours
  for (int i = 0; i < kMaxGraphEntities; ++i) {
    EXPECT_EQ(s.depth[i], i == 0 ? 1 : kMaxGraphEntities) << i;  // a Hamiltonian path ends anywhere
    const uint64_t all_but_i = ((uint64_t{1} << kMaxGraphEntities) - 1) & ~(uint64_t{1} << i);
    EXPECT_EQ(s.ancestor_mask[i], i == 0 ? 0u : all_but_i) << i;
  }
  g.num_entities = kMaxGraphEntities + 1;  // refused before any search
  g.adjacency.assign(g.num_entities * g.num_entities, 1);
  EXPECT_THROW(ComputeSubgoalStructure(g), std::invalid_argument);
}

TEST(GraphTest, DescribeListsEdges) {
  EXPECT_EQ(DescribeGraph(FromEdges(3, {{0, 1}, {1, 2}})), "action->0, 0->1, 1->2");
}

// Relational Rearrange 4's shape with a tie both ways: action -> arm 0, 0 -> 2, 0 -> 3, 0 -> 4,
// 2 <-> 3; object 1 has no edge (the static puck).
InteractionGraph TiedCatalogue() { return FromEdges(5, {{0, 2}, {0, 3}, {0, 4}, {2, 3}, {3, 2}}); }

TEST(EpisodeSubgoalStructureTest, EveryEntityPresentIsTheCatalogueStructure) {
  const std::vector<uint16_t> kinds = {0, 1, 2, 3, 4};
  const SubgoalStructure s = EpisodeSubgoalStructure(TiedCatalogue(), kinds);
  // by hand: 2 is reached by a->0->2 and a->0->3->2, so P = {0, 3} and depth 3; 3 likewise
  EXPECT_EQ(s.depth, (std::vector<int>{1, -1, 3, 3, 2}));
  EXPECT_EQ(s.ancestor_mask, (std::vector<uint64_t>{0, 0, 0b01001, 0b00101, 0b00001}));
  const SubgoalStructure c = ComputeSubgoalStructure(TiedCatalogue());
  EXPECT_EQ(s.depth, c.depth);
  EXPECT_EQ(s.ancestor_mask, c.ancestor_mask);
}

TEST(EpisodeSubgoalStructureTest, AnAbsentObjectBreaksThePathsThroughIt) {
  // object 3 absent: episode entities 0, 1, 2, 3 are catalogue 0, 1, 2, 4; object 2 loses
  // the path through 3 (depth 2, P = {arm}), object 4 keeps its own
  const std::vector<uint16_t> kinds = {0, 1, 2, 4};
  const SubgoalStructure s = EpisodeSubgoalStructure(TiedCatalogue(), kinds);
  EXPECT_EQ(s.depth, (std::vector<int>{1, -1, 2, 2}));
  EXPECT_EQ(s.ancestor_mask, (std::vector<uint64_t>{0, 0, 0b0001, 0b0001}));
  EXPECT_EQ(s.SubgoalEntities(), (std::vector<int>{0, 2, 3}));
}

TEST(EpisodeSubgoalStructureTest, IndicesAreTheEpisodesBitsTooWhenObjectOneIsAbsent) {
  // object 1 absent: catalogue 2 and 3 are episode entities 1 and 2, and each other's ancestor
  const std::vector<uint16_t> kinds = {0, 2, 3, 4};
  const SubgoalStructure s = EpisodeSubgoalStructure(TiedCatalogue(), kinds);
  EXPECT_EQ(s.depth, (std::vector<int>{1, 3, 3, 2}));
  EXPECT_EQ(s.ancestor_mask, (std::vector<uint64_t>{0, 0b0101, 0b0011, 0b0001}));
}

TEST(EpisodeSubgoalStructureTest, OrderOfKindsIsTheEpisodes) {
  const std::vector<uint16_t> kinds = {0, 4, 2};
  const SubgoalStructure s = EpisodeSubgoalStructure(TiedCatalogue(), kinds);
  EXPECT_EQ(s.depth, (std::vector<int>{1, 2, 2}));
  EXPECT_EQ(s.ancestor_mask, (std::vector<uint64_t>{0, 0b001, 0b001}));
}

TEST(EpisodeSubgoalStructureTest, WithoutTheDrivenEntityNothingIsASubgoal) {
  const std::vector<uint16_t> kinds = {2, 3};
  const SubgoalStructure s = EpisodeSubgoalStructure(TiedCatalogue(), kinds);
  EXPECT_EQ(s.depth, (std::vector<int>{-1, -1}));
  EXPECT_TRUE(s.SubgoalEntities().empty());
}

TEST(EpisodeSubgoalStructureTest, RefusesKindsOutsideTheGraphOrRepeated) {
  const std::vector<uint16_t> outside = {0, 5}, twice = {0, 2, 2};
  EXPECT_THROW(EpisodeSubgoalStructure(TiedCatalogue(), outside), std::invalid_argument);
  EXPECT_THROW(EpisodeSubgoalStructure(TiedCatalogue(), twice), std::invalid_argument);
}

TEST(CatalogueSubgoalsTest, WithoutAGraphEveryPresentEntityIsASubgoal) {
  const CatalogueSubgoals none;
  const std::vector<int> kinds = {0, 2, 4};
  const SubgoalStructure s = none.For(kinds);
  EXPECT_EQ(s.depth, (std::vector<int>{1, 1, 1}));
  EXPECT_EQ(s.ancestor_mask, (std::vector<uint64_t>{0, 0, 0}));
  const CatalogueSubgoals tied{TiedCatalogue()};
  EXPECT_EQ(tied.For(kinds).depth, (std::vector<int>{1, 2, 2}));
}

}  // namespace
}  // namespace srics::rl
