#pragma once
// The graph service's loop, without any transport: it pulls explore episodes from an
// EpisodeSource, trains the GNN until the thresholded graph is stable, publishes the
// versioned graph to a GraphSink, saves it, and on restart re-publishes the saved graph
// without retraining. A thin main supplies a DDS source and sink and a stop flag.
//
//   GraphService service(config, options, &source, &sink, [](const Progress& p) { ... });
//   int code = service.Run(stop_flag);   // returns when done, stopped, or the source closes

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/config/graph_config.h"
#include "common/rl/episode.h"
#include "graph_service/dataset.h"
#include "graph_service/learned_graph.h"
#include "graph_service/trainer.h"

namespace srics::graph {

// Where explore episodes come from (DDS Episode samples, or an environment in process).
// Threading: only called from the thread running GraphService::Run.
class EpisodeSource {
 public:
  virtual ~EpisodeSource() = default;
  // Appends the episodes available now, waiting at most `timeout` for the first one.
  // Returns false once the source is closed and will never deliver again.
  // Episodes are untrusted: the service validates each one and counts what it drops.
  virtual bool Poll(std::chrono::milliseconds timeout, std::vector<rl::Episode>* out) = 0;
};

// Where learned graphs go (the InteractionGraph topic, transient-local, keep-last 1).
// Threading: only called from the thread running GraphService::Run.
class GraphSink {
 public:
  virtual ~GraphSink() = default;
  // Publishes `graph`; versions increase across publications of one state directory.
  // May throw; the service logs and retries on the next publication attempt.
  virtual void Publish(const LearnedGraph& graph) = 0;
};

// What the service is doing, for progress displays and NodeStatus.
struct Progress {
  enum class Phase { kLoading, kCollecting, kTraining, kPublished, kStopped };
  Phase phase = Phase::kLoading;
  int episodes = 0;            // accepted into the data set
  int target_episodes = 0;     // data set size wanted
  int dropped = 0;             // refused (wrong mode, layout, non-finite, ...)
  std::string last_drop_reason;
  int64_t updates = 0;         // GNN training updates done
  double train_loss = 0;       // MSE per transition of the last batch
  double held_out_loss = -1;   // at the last evaluation (-1: none yet)
  double held_out_zero_loss = -1;  // held-out MSE of predicting no motion
  // per entity held-out MSE and its no-motion baseline (which entities are predicted well)
  std::vector<double> entity_loss, entity_zero_loss;
  int stable_evaluations = 0;  // consecutive evaluations with an unchanged graph
  std::string graph;           // current thresholded graph (rl::DescribeGraph)
  std::vector<double> mean_weights;  // current mean weights (N x N)
  uint64_t published_version = 0;    // 0: nothing published yet
  double elapsed_seconds = 0;  // since Run started
};

// Phase name for logs ("collecting", ...).
const char* PhaseName(Progress::Phase phase);

// Service settings that are not GNN hyperparameters.
struct ServiceOptions {
  std::string state_dir;        // holds graph.json (+ pictures); empty = no saving/loading
  uint64_t seed = 1;            // data split, initial weights, batches, Gumbel noise
  bool render_pictures = true;  // graph.png and graph_weights.png via graphviz
  std::chrono::milliseconds poll_timeout{200};
};

class GraphService {
 public:
  using ProgressCallback = std::function<void(const Progress&)>;

  // source and sink must outlive the service; on_progress may be empty.
  GraphService(const config::GraphConfig& config, const ServiceOptions& options,
               EpisodeSource* source, GraphSink* sink, ProgressCallback on_progress);

  // Runs the whole service: load-and-republish, or collect, train, publish, save. Checks
  // `stop` between updates and polls. Returns 0 when a graph was published, 1 when stopped
  // or the source closed before that.
  int Run(const std::atomic<bool>& stop);

  // The published graph, if any.
  const std::optional<LearnedGraph>& published() const { return published_; }
  const Progress& progress() const { return progress_; }
  // Path of the saved graph file ("" without a state directory).
  std::string graph_path() const;

 private:
  bool LoadSaved();
  bool Collect(const std::atomic<bool>& stop);
  bool Train(const std::atomic<bool>& stop);
  void Finish();
  void Report();

  config::GraphConfig config_;
  ServiceOptions options_;
  EpisodeSource* source_;
  GraphSink* sink_;
  ProgressCallback on_progress_;
  Progress progress_;
  std::unique_ptr<GraphDataset> data_;
  std::unique_ptr<GnnTrainer> trainer_;
  std::optional<LearnedGraph> current_;    // last evaluated graph
  std::optional<LearnedGraph> published_;
  uint64_t next_version_ = 1;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace srics::graph
