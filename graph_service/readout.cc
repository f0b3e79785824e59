#include "graph_service/readout.h"

#include <algorithm>
#include <cstddef>

#include "graph_service/learned_graph.h"

namespace srics::graph_service {

namespace {
// an entity whose no-motion error is below this fraction of the largest entity's never moves
// (a static object's is exactly 0 in MuJoCo)
constexpr double kNeverMovesFraction = 1e-6;
}  // namespace

std::vector<double> ReadOutScores(const EdgeStatistics& stats, const config::GraphConfig& config, int action_entity) {
  const bool cut = config.readout == config::GraphReadout::kCut;
  std::vector<double> scores = cut ? stats.cut_score : stats.mean_weight;
  const int n = stats.num_entities;
  if (!cut && stats.apart_weight.size() == scores.size()) {
    // object pairs: their weight while apart (graph.object_edges: apart); the arm's: every step
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (i != action_entity && j != action_entity)
          scores[static_cast<size_t>(i) * n + j] = stats.apart_weight[static_cast<size_t>(i) * n + j];
  }
  if (!cut && !stats.training_mean_weight.empty()) {
    // refinement: an edge counts when it is used in random exploration or in the agent's own
    // episodes (the larger mean), so a relation only the policy's pushes reveal joins the graph
    // and an object the policy neglects keeps its edges
    for (size_t i = 0; i < scores.size(); ++i) scores[i] = std::max(scores[i], stats.training_mean_weight[i]);
  }
  // which entities move; with object sets the per-entity errors are per position in the
  // episode, not per catalogue identity: then every object counts (a pair touching a static
  // object is wrong in either direction, so this never spoils an exact graph)
  std::vector<bool> moving(n, true);
  if (stats.held_out_entity_zero_mse.size() == static_cast<size_t>(n))
    moving = MovingEntities(stats.held_out_entity_zero_mse, config.static_variance_fraction);
  // nothing enters an entity that does not move: the model may still route a little of the
  // others' error through it (relational-4-spring with the onset weight: arm -> static puck
  // 0.075), but there is no motion for an edge to explain. The cut read-out never scores them.
  // Nor does anything leave one: an object that never moves acts on others only when they
  // run into it (contact, which the graphs leave out), and a recurrent receiver takes in the
  // obstacle's place before it gets there, so its gate is open while apart too (the slow
  // learning test's static puck -> free puck, relational-4-spring's static puck -> pucks
  // 0.06-0.09 with the onset weight). A tie to a static object would be missed (no preset or
  // random table has one).
  // "Never moves" is stricter than `moving` (1% of the largest variance): an object the arm
  // seldom reaches moves that little and still has its edge (the toy world's second puck).
  std::vector<bool> still(n, false);
  if (stats.held_out_entity_zero_mse.size() == static_cast<size_t>(n)) {
    const std::vector<bool> moves_at_all = MovingEntities(stats.held_out_entity_zero_mse, kNeverMovesFraction);
    for (int j = 0; j < n; ++j) still[j] = !moves_at_all[j];
  }
  for (int j = 0; j < n; ++j)
    if (still[j])
      for (int i = 0; i < n; ++i) scores[static_cast<size_t>(i) * n + j] = scores[static_cast<size_t>(j) * n + i] = 0.0;
  if (config.reciprocal_object_edges) scores = ReciprocalObjectScores(scores, action_entity, moving);
  // the data's tie evidence sets each object pair's bar: a pair seen pulling at a distance is
  // kept above tied_pair_threshold, any other (a contact the recurrent model remembers while
  // apart: two free pucks up to 0.062 on the tuning tables) above untied_pair_threshold
  if (!cut && stats.tie_evidence_counted && config.pair_bars_on())
    scores = CalibrateObjectPairs(scores, action_entity, moving, stats.tied_by_evidence, config.threshold,
                                  config.tied_pair_threshold, config.untied_pair_threshold);
  if (config.object_pair_share > 0)
    scores = CutWeakObjectPairs(scores, action_entity, moving, config.object_pair_share);
  if (config.object_ties == config::ObjectTies::kOneWay) {
    // oriented by the every-step mean weights: the graph file keeps them, so the direction can
    // be checked and derived again from a published graph (the scores of a reciprocal pair are
    // equal both ways)
    const std::vector<double>& orientation = stats.mean_weight.size() == scores.size() ? stats.mean_weight : scores;
    scores = OneWayObjectTies(scores, orientation, action_entity, cut ? config.cut_threshold : config.threshold);
  }
  return scores;
}

}  // namespace srics::graph_service
