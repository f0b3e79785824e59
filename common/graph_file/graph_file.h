#pragma once
// The interaction graph as a file (DIR/graph.json): what the graph service publishes (the
// thresholded graph with its edge scores, action node, ancestor sets and depths, and where it
// came from), saved and loaded as validated JSON (the file is untrusted on restart and when a
// run folder comes from elsewhere), and drawn as pictures with graphviz. The graph service
// writes it; the launcher, `srics eval`, `srics compare` and the dashboard read it without
// linking the GNN.

#include <cstdint>
#include <string>
#include <vector>

#include "common/rl/graph.h"
#include "common/rl/updates.h"

namespace srics::graph_file {

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

// True when two graphs keep the same edges and action entity (weights may differ).
// Keeps the edges i -> j (i != j) whose score exceeds `threshold`, attaches the action node
// to `action_entity`, and derives ancestor sets and depths with rl::ComputeSubgoalStructure.
// edge_scores and mean_weights of the result are `scores` (diagonal zeroed); a caller with
// another read-out sets mean_weights and readout afterwards. Throws std::invalid_argument on
// malformed input (size not N x N, N outside [2, rl::kMaxGraphEntities], action entity out of
// range, scores not finite).
LearnedGraph AggregateGraph(int num_entities, const std::vector<double>& scores, double threshold, int action_entity);

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

// The graph as the topic carries it (what every role subscribes to).
rl::GraphUpdate ToGraphUpdate(const LearnedGraph& graph);

}  // namespace srics::graph_file
