#pragma once
// The read-out: from the trained GNN's edge statistics to the scores the threshold applies to
// (graph_service/README.md, "Read-out"). No state: the service calls it at every evaluation.

#include <vector>

#include "common/config/graph_config.h"
#include "graph_service/trainer.h"

namespace srics::graph_service {

// The edge scores the threshold applies to: the read-out's (graph.readout: the mean weights,
// with refinement the larger of random and training data; or the cut scores), every object ->
// object pair made reciprocal (graph.reciprocal_object_edges; ReciprocalObjectScores) among the
// entities that move, calibrated by the tie evidence when it was counted (the mean_weight
// read-out with graph.tied_pair_threshold and untied_pair_threshold; CalibrateObjectPairs),
// then the weak object pairs cut (graph.object_pair_share; CutWeakObjectPairs),
// then, with graph.object_ties: one_way, the ties made one way by the mean weights (OneWayObjectTies).
std::vector<double> ReadOutScores(const EdgeStatistics& stats, const config::GraphConfig& config, int action_entity);

}  // namespace srics::graph_service
