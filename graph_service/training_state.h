#pragma once
// A graph service's unfinished training, saved and restored whole (the service's
// graph_training.srics): the data set being collected, then split; the GNN trainer once the data
// set is full; the refinement's ring of the run's training episodes; and the loop's counters
// about them. The loop (service.h) owns one and knows nothing of its file format.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/config/graph_config.h"
#include "common/graph_file/graph_file.h"
#include "common/nn/serialize.h"
#include "graph_service/dataset.h"
#include "graph_service/trainer.h"

namespace srics::graph_service {

struct TrainingState {
  std::unique_ptr<GraphDataset> data;
  std::unique_ptr<GnnTrainer> trainer;        // once data holds graph.episodes
  std::unique_ptr<GraphDataset> refine_data;  // graph.refine_after_publish: a ring as large as the training split
  int dropped = 0;                            // explore episodes refused
  int stable = 0;                             // evaluations in a row with an unchanged graph
  int refine_cursor = 0;                      // the ring's next place once it is full
  int refine_episodes = 0;                    // training episodes taken in since the first publication
  bool refine_decided = false;                // the edges were decided again on training episodes
  // of the evaluations after the warm-up and the KL ramp, the one with the lowest held-out loss
  // (graph.publish: lowest_held_out_loss publishes it)
  std::optional<graph_file::LearnedGraph> lowest_loss;

  // The checkpoint sections: graph.data, graph.service (the counters), graph.refine_data when
  // refining, graph.lowest_loss once there is one (the graph file's JSON), and the trainer's.
  std::vector<nn::CheckpointSection> Save() const;

  // What Save wrote, into data sets of `empty`'s shape; the trainer is made again (the data set
  // split with `seed`, `contact_radius` given) when the data set is full. Throws
  // nn::CheckpointError naming `path` and what does not fit the run (`config`).
  struct RestoreOptions {
    uint64_t seed = 0;
    int refine_episode_steps = 0;
    std::vector<double> contact_radius;
  };
  static TrainingState Restore(const std::vector<nn::CheckpointSection>& sections, const std::string& path,
                               const GraphDataset& empty, const config::GraphConfig& config,
                               const RestoreOptions& options);
};

}  // namespace srics::graph_service
