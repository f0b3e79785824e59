#pragma once
// Reading the interaction graph out of the model's scores: the rules for object pairs
// (reciprocal, weak contacts cut, ties one way). The product, a graph_file::LearnedGraph, is
// kept under a threshold by graph_file::AggregateGraph (common/graph_file: the graph as a file,
// its validation and its pictures).

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/graph_file/graph_file.h"
#include "common/rl/graph.h"

namespace srics::graph_service {

// The graph file's types and functions, which the read-out builds and the service saves.
using graph_file::AggregateGraph;
using graph_file::GraphDot;
using graph_file::GraphFromJson;
using graph_file::GraphToJson;
using graph_file::HeatMapDot;
using graph_file::LearnedGraph;
using graph_file::LoadGraph;
using graph_file::RenderDotToPng;
using graph_file::SameStructure;
using graph_file::SaveGraph;
using graph_file::SaveGraphWithPictures;
using graph_file::ToGraphUpdate;

// Scores with every object -> object pair made reciprocal: for i, j both moving and neither
// `arm`, scores[i][j] = scores[j][i] = the larger of the two. Edges from or into the arm and
// into an entity that does not move are left as they are. Throws std::invalid_argument when
// the sizes do not match or arm is out of range.
std::vector<double> ReciprocalObjectScores(const std::vector<double>& scores, int arm, const std::vector<bool>& moving);

// Scores with every weak object -> object edge set to 0: for i, j both moving and neither
// `arm`, i -> j is cut when its score is below `share` times the largest score of any
// object -> object edge from or into i or j (either direction). Other edges are left as they
// are; share 0 returns the scores unchanged. Throws std::invalid_argument when the sizes do
// not match, arm is out of range or share is outside [0, 1].
std::vector<double> CutWeakObjectPairs(const std::vector<double>& scores, int arm, const std::vector<bool>& moving,
                                       double share);

// Scores with every object -> object pair calibrated by the data's tie evidence: for i, j both
// moving and neither `arm`, the score is multiplied by threshold / tied_threshold when {i, j}
// (either order) is in `tied_pairs`, by threshold / untied_threshold otherwise, and capped at 1,
// so that the one threshold keeps a pair the evidence names above tied_threshold and any other
// above untied_threshold. Edges from or into the arm and into an entity that does not move are
// left as they are. Throws std::invalid_argument when the sizes do not match, arm is out of range,
// a pair names an entity out of range or a threshold is not above 0.
std::vector<double> CalibrateObjectPairs(const std::vector<double>& scores, int arm, const std::vector<bool>& moving,
                                         const std::vector<std::pair<int, int>>& tied_pairs, double threshold,
                                         double tied_threshold, double untied_threshold);

// Scores with the object -> object edges over `threshold` made one way (graph.object_ties:
// one_way): they are taken in decreasing order of `orientation` (the model's mean edge weights
// over the data set; equal weights: i -> j before j -> i for i < j, then in index order) and an
// edge that would close a directed cycle with the edges taken before it gets score 0. A pair
// kept both ways thus keeps the direction with the larger orientation weight, and the objects'
// edges form a DAG. Edges from or into `arm` and edges at or under the threshold are left as
// they are. Throws std::invalid_argument when the sizes do not match or arm is out of range.
std::vector<double> OneWayObjectTies(const std::vector<double>& scores, const std::vector<double>& orientation, int arm,
                                     double threshold);

// `graph` with its object ties made one way: OneWayObjectTies of its edge scores oriented by
// its mean weights at its threshold, then adjacency, ancestor sets and depths derived again;
// the other fields are kept. For graphs read from files (a learned graph's read-out applies the
// rule itself when graph.object_ties is one_way).
LearnedGraph WithOneWayObjectTies(const LearnedGraph& graph);

}  // namespace srics::graph_service
