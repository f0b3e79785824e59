#include "graph_service/learned_graph.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace srics::graph_service {

namespace {

// N of an N x N score matrix over the entities of `moving`; throws std::invalid_argument naming
// `function` when the sizes do not match or arm is out of range.
int CheckedObjectScores(const char* function, const std::vector<double>& scores, int arm,
                        const std::vector<bool>& moving) {
  const int n = static_cast<int>(moving.size());
  if (scores.size() != static_cast<size_t>(n) * n)
    throw std::invalid_argument(std::string(function) + ": score matrix is not N x N");
  if (arm < 0 || arm >= n) throw std::invalid_argument(std::string(function) + ": arm out of range");
  return n;
}

// Whether i -> j joins two different objects that both move (neither the arm).
bool MovingObjectPair(int i, int j, int arm, const std::vector<bool>& moving) {
  return i != j && i != arm && j != arm && moving[i] && moving[j];
}

}  // namespace

std::vector<double> ReciprocalObjectScores(const std::vector<double>& scores, int arm,
                                           const std::vector<bool>& moving) {
  const int n = CheckedObjectScores("ReciprocalObjectScores", scores, arm, moving);
  std::vector<double> out = scores;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (!MovingObjectPair(i, j, arm, moving)) continue;
      const size_t ij = static_cast<size_t>(i) * n + j, ji = static_cast<size_t>(j) * n + i;
      out[ij] = out[ji] = std::max(scores[ij], scores[ji]);
    }
  return out;
}

std::vector<double> CutWeakObjectPairs(const std::vector<double>& scores, int arm, const std::vector<bool>& moving,
                                       double share) {
  const int n = CheckedObjectScores("CutWeakObjectPairs", scores, arm, moving);
  if (!(share >= 0 && share <= 1)) throw std::invalid_argument("CutWeakObjectPairs: share outside [0, 1]");
  auto object_pair = [&](int i, int j) { return MovingObjectPair(i, j, arm, moving); };
  // each object's strongest pair, over both directions
  std::vector<double> strongest(n, 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (object_pair(i, j)) {
        const double s = scores[static_cast<size_t>(i) * n + j];
        strongest[i] = std::max(strongest[i], s);
        strongest[j] = std::max(strongest[j], s);
      }
  std::vector<double> out = scores;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const size_t ij = static_cast<size_t>(i) * n + j;
      if (object_pair(i, j) && scores[ij] < share * std::max(strongest[i], strongest[j])) out[ij] = 0.0;
    }
  return out;
}

std::vector<double> CalibrateObjectPairs(const std::vector<double>& scores, int arm, const std::vector<bool>& moving,
                                         const std::vector<std::pair<int, int>>& tied_pairs, double threshold,
                                         double tied_threshold, double untied_threshold) {
  const int n = CheckedObjectScores("CalibrateObjectPairs", scores, arm, moving);
  if (!(threshold > 0 && tied_threshold > 0 && untied_threshold > 0))
    throw std::invalid_argument("CalibrateObjectPairs: thresholds must be above 0");
  std::vector<bool> tied(static_cast<size_t>(n) * n, false);
  for (const auto& [i, j] : tied_pairs) {
    if (i < 0 || i >= n || j < 0 || j >= n) throw std::invalid_argument("CalibrateObjectPairs: tied pair out of range");
    tied[static_cast<size_t>(i) * n + j] = tied[static_cast<size_t>(j) * n + i] = true;
  }
  std::vector<double> out = scores;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (!MovingObjectPair(i, j, arm, moving)) continue;
      const size_t ij = static_cast<size_t>(i) * n + j;
      // capped: a graph file's scores are probabilities in [0, 1]
      out[ij] = std::min(1.0, scores[ij] * threshold / (tied[ij] ? tied_threshold : untied_threshold));
    }
  return out;
}

std::vector<double> OneWayObjectTies(const std::vector<double>& scores, const std::vector<double>& orientation, int arm,
                                     double threshold) {
  int n = 0;
  while (static_cast<size_t>(n) * n < scores.size()) ++n;
  if (static_cast<size_t>(n) * n != scores.size() || orientation.size() != scores.size())
    throw std::invalid_argument("OneWayObjectTies: scores and orientation are not both N x N");
  if (arm < 0 || arm >= n) throw std::invalid_argument("OneWayObjectTies: arm out of range");
  auto at = [n](int i, int j) { return static_cast<size_t>(i) * n + j; };
  std::vector<std::pair<int, int>> edges;  // the object -> object edges the threshold keeps
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j && i != arm && j != arm && scores[at(i, j)] > threshold) edges.emplace_back(i, j);
  // strongest first; equal weights: the lower sender first (the pair i < j: i -> j stays)
  std::stable_sort(edges.begin(), edges.end(), [&](const std::pair<int, int>& a, const std::pair<int, int>& b) {
    return orientation[at(a.first, a.second)] > orientation[at(b.first, b.second)];
  });
  std::vector<uint8_t> taken(scores.size(), 0);
  auto reaches = [&](int from, int to) {  // a directed path over the edges taken so far
    std::vector<bool> seen(n, false);
    std::vector<int> stack{from};
    seen[from] = true;
    while (!stack.empty()) {
      const int k = stack.back();
      stack.pop_back();
      if (k == to) return true;
      for (int m = 0; m < n; ++m)
        if (taken[at(k, m)] && !seen[m]) seen[m] = true, stack.push_back(m);
    }
    return false;
  };
  std::vector<double> out = scores;
  for (const auto& [i, j] : edges) {
    if (reaches(j, i))
      out[at(i, j)] = 0.0;  // would close a cycle: the weaker direction of a pair
    else
      taken[at(i, j)] = 1;
  }
  return out;
}

LearnedGraph WithOneWayObjectTies(const LearnedGraph& graph) {
  const int n = graph.num_entities();
  const std::vector<double>& orientation =
      graph.mean_weights.size() == graph.edge_scores.size() ? graph.mean_weights : graph.edge_scores;
  LearnedGraph out = graph;
  const LearnedGraph derived =
      AggregateGraph(n, OneWayObjectTies(graph.edge_scores, orientation, graph.graph.action_entity, graph.threshold),
                     graph.threshold, graph.graph.action_entity);
  out.graph = derived.graph;
  out.structure = derived.structure;
  out.edge_scores = derived.edge_scores;
  return out;
}

}  // namespace srics::graph_service
