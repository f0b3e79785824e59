#pragma once
// The graph service's product: the thresholded interaction graph with its mean edge weights,
// action node, ancestor sets and depths, and where it came from. Built from mean weights by
// aggregation, saved to and loaded from a JSON file (validated: the file is untrusted on
// restart), and drawn as pictures with graphviz.

#include <cstdint>
#include <string>
#include <vector>

#include "common/rl/graph.h"

namespace srics::graph_service {

struct LearnedGraph {
  uint64_t version = 0;            // 1, 2, ... per publication of a new graph
  rl::InteractionGraph graph;      // adjacency (i acts on j) and the action entity
  rl::SubgoalStructure structure;  // ancestor sets and depths of `graph`
  // how the edges were read out of the model: "cut" or "mean_weight" (the paper's)
  std::string readout = "mean_weight";
  // N x N, [i * N + j], diagonal 0, each in [0, 1]: the read-out's score of each edge (the
  // cut score, or the mean weight); kept edges have a score > threshold
  std::vector<double> edge_scores;
  double threshold = 0.06;
  std::vector<double> mean_weights;        // N x N: the model's mean edge weights (informational)
  std::vector<double> action_correlation;  // per entity, how its motion follows the action
  std::vector<int> entity_kinds;           // kind of each entity (0 = arm)
  double held_out_loss = 0;                // held-out MSE per transition of the final model
  int64_t updates = 0;                     // training updates behind the graph
  int episodes = 0;                        // episodes in its data set

  int num_entities() const { return graph.num_entities; }
};

// Keeps the edges i -> j (i != j) whose score exceeds `threshold`, attaches the action node
// to `action_entity`, and derives ancestor sets and depths with rl::ComputeSubgoalStructure.
// edge_scores and mean_weights of the result are `scores` (diagonal zeroed); a caller with
// another read-out sets mean_weights and readout afterwards. Throws std::invalid_argument on
// malformed input (size not N x N, N outside [2, rl::kMaxGraphEntities], action entity out of
// range, scores not finite).
LearnedGraph AggregateGraph(int num_entities, const std::vector<double>& scores, double threshold, int action_entity);

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

// True when two graphs keep the same edges and action entity (weights may differ).
bool SameStructure(const rl::InteractionGraph& a, const rl::InteractionGraph& b);

// Writes `graph` as JSON to `path` durably (files::WriteFileDurably: a temporary file, fsynced,
// renamed into place, the folder fsynced). The file carries a
// format tag and version and an FNV-1a checksum of its content. Throws std::runtime_error on
// I/O failure.
void SaveGraph(const LearnedGraph& graph, const std::string& path);

// Reads a file written by SaveGraph. Throws std::runtime_error naming what is wrong when the
// file is missing, truncated, corrupted (checksum), of another format or version, or
// inconsistent (sizes, weights outside [0, 1], adjacency that does not match the weights and
// threshold, ancestor sets or depths that do not follow from the adjacency).
LearnedGraph LoadGraph(const std::string& path);

// The JSON text SaveGraph writes (exposed for tests).
std::string GraphToJson(const LearnedGraph& graph);
// Parses and validates JSON text as LoadGraph does.
LearnedGraph GraphFromJson(const std::string& text);

// Graphviz source of the graph: an action node, the entities, and the kept edges labelled
// with their mean weights; entity 0 is called "arm", the others "puck i".
std::string GraphDot(const LearnedGraph& graph);
// Graphviz source of a heat map of the mean weight matrix (a table of coloured cells with
// the values; rows: from, columns: to).
std::string HeatMapDot(const LearnedGraph& graph);

// Draws graphviz source into the PNG `png_path` with `dot` (fed on its standard input).
// Returns false with the reason in *error when `dot` is missing or fails; never throws.
bool RenderDotToPng(const std::string& dot_text, const std::string& png_path, std::string* error);

// Writes <prefix>.json, <prefix>.dot, <prefix>_weights.dot and, when graphviz `dot` is on
// the PATH, <prefix>.png and <prefix>_weights.png. Returns the pictures that could not be
// rendered (empty when all were), never throws for a missing `dot`.
std::string SaveGraphWithPictures(const LearnedGraph& graph, const std::string& prefix);

}  // namespace srics::graph_service
