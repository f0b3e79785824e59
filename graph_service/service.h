#pragma once
// The graph service's loop, without any transport: it pulls explore episodes from an
// EpisodeSource, trains the GNN until the thresholded graph is stable, publishes the
// versioned graph (and its NodeStatus) to a GraphSink, saves it, and on restart re-publishes
// the saved graph without retraining. The srics-graph main supplies DDS links; the
// in-process run the in-memory bus.
//
//   GraphService service(config, options, &source, &sink, [](const Progress& p) { ... });
//   int code = service.Run(stop_flag);   // returns when published, stopped, or the source closes
//   // or step it (Step keeps draining the source after publishing: stop on the phase):
//   while (service.progress().phase != Progress::Phase::kPublished &&
//          service.Step() != StepResult::kDone) {}

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/config/config.h"
#include "common/config/graph_config.h"
#include "common/links/links.h"
#include "common/rl/agent_shape.h"
#include "common/rl/episode.h"
#include "graph_service/dataset.h"
#include "graph_service/learned_graph.h"
#include "graph_service/trainer.h"
#include "graph_service/training_state.h"

namespace srics::graph_service {

using links::EpisodeSource;
using links::GraphSink;

// What the service is doing, for progress displays and NodeStatus.
struct Progress {
  enum class Phase { kLoading, kCollecting, kTraining, kPublished, kStopped };
  Phase phase = Phase::kLoading;
  int episodes = 0;         // accepted into the data set
  int target_episodes = 0;  // data set size wanted
  int dropped = 0;          // refused (wrong mode, layout, non-finite, ...)
  std::string last_drop_reason;
  int64_t updates = 0;             // GNN training updates done
  int64_t skipped_updates = 0;     // of them: skipped, a non-finite loss or unusable gradient (since start)
  double train_loss = 0;           // MSE per transition of the last batch
  double held_out_loss = -1;       // at the last evaluation (-1: none yet)
  double held_out_zero_loss = -1;  // held-out MSE of predicting no motion
  // per entity held-out MSE and its no-motion baseline (which entities are predicted well)
  std::vector<double> entity_loss, entity_zero_loss;
  // per graph entity, the data set's onsets of motion with nothing in reach (a tie's evidence;
  // GnnTrainer::onsets_at_a_distance), once training starts
  std::vector<int64_t> onsets_at_a_distance;
  std::vector<int64_t> onsets_while_moving;  // per ordered pair (GnnTrainer::onsets_while_moving)
  // the object pairs whose edges pay graph.tie_kl_factor times the KL and are kept above
  // graph.tied_pair_threshold (GnnTrainer::tied_by_evidence), when the evidence was counted
  std::vector<std::pair<int, int>> tied_by_evidence;
  bool tie_evidence_counted = false;
  int stable_evaluations = 0;        // consecutive evaluations with an unchanged graph
  std::string graph;                 // current thresholded graph (rl::DescribeGraph)
  std::vector<double> edge_scores;   // current read-out scores (N x N), thresholded
  std::vector<double> mean_weights;  // current mean weights (N x N)
  uint64_t published_version = 0;    // 0: nothing published yet
  // graph.refine_after_publish: training episodes taken in since the first publication
  bool refining = false;
  int refine_episodes = 0;
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
  rl::EpisodeLimits limits;  // what an episode of this run looks like (default: any layout)
  // The data set's layout, entity kinds and action size: the run's, from its config
  // (rl::RunShape::full); explore episodes of any other shape are dropped. The role
  // programs always set it. Unset (toy worlds in tests) the first valid episode fixes it.
  std::optional<DatasetShape> shape;
  // each graph entity's footprint bounding radius in metres (the arm's hand box, then the
  // catalogue's objects), for graph.object_edges: apart; empty: object edges over every step
  std::vector<double> contact_radius;
  int updates_per_step = 10;  // GNN updates per Step (each Step stays well under a second)
  // the run's training episode length (actors.train_episode_steps): with
  // graph.refine_after_publish the service refines from episodes of this length
  int refine_episode_steps = 0;
  double status_period_s = 1;  // NodeStatus to the sink this often
};

// The options a run's config implies (both the srics-graph process and the in-process run):
// its seed, shape, limits, status period and training episode length; state in `state_dir`.
ServiceOptions ServiceOptionsFor(const config::Config& config, const rl::RunShape& run_shape,
                                 const std::string& state_dir);

enum class StepResult {
  kWorked,  // took episodes, trained, or published
  kIdle,    // waits for episodes, or has published and only drains the source
  kDone,    // Run's end: the graph is published (Step keeps draining after that), or the
            // source closed before
};

class GraphService {
 public:
  using ProgressCallback = std::function<void(const Progress&)>;

  // source and sink must outlive the service; on_progress may be empty.
  GraphService(const config::GraphConfig& config, const ServiceOptions& options, EpisodeSource* source, GraphSink* sink,
               ProgressCallback on_progress);

  // One unit of work: the first Step loads and re-publishes a saved graph if there is one;
  // then each Step collects the episodes the source has (waiting at most `wait`), or does
  // updates_per_step GNN updates (an evaluation at every eval_every_updates), or publishes.
  // After the publication Steps drain the source (the Episode topic must keep flowing) and
  // return kIdle; with graph.refine_after_publish they take the run's training episodes in,
  // train on (refine_updates_per_episode updates each) and publish the next version when
  // the evaluated graph has differed from the published one for stable_evaluations
  // evaluations. kDone only when the source closed before a graph was published.
  StepResult Step(std::chrono::milliseconds wait = std::chrono::milliseconds(0));

  // Steps until a graph is published (returns 0), `stop`, or the source closes (returns 1).
  int Run(const std::atomic<bool>& stop);
  // Says goodbye: the phase becomes kStopped and a last NodeStatus ("stopping") goes out.
  void Stop();

  // The published graph, if any.
  const std::optional<LearnedGraph>& published() const { return published_; }
  const Progress& progress() const { return progress_; }
  // Path of the saved graph file ("" without a state directory).
  std::string graph_path() const;
  // Path of the unfinished training's checkpoint ("" without a state directory): the data
  // set while collecting, then also the GNN at every evaluation; removed once the graph is
  // published. A restarted service resumes from it instead of starting over.
  std::string training_path() const;

 private:
  bool LoadSaved();
  bool LoadTraining();
  void SaveTraining();
  StepResult CollectStep(std::chrono::milliseconds wait);
  void StartTraining();
  void TrainStep();
  void UpdateModel();  // one GNN update; a skipped one is counted and its streak logged
  void EvaluateGraph();
  void Finish();
  // the progress fields that name a graph: its edges, scores and mean weights
  void ShowGraph(const LearnedGraph& graph);
  void PublishCurrent();  // current_ as the next version: saved, published
  void StartRefinement();
  StepResult RefineStep(std::chrono::milliseconds wait);
  int RefineCapacity() const;  // the ring's size: the training split's
  double RefineShare() const;  // share of a batch's windows from training episodes now
  void SyncProgress();         // the counters TrainingState keeps, into progress_
  void Report();
  void PublishStatus(bool force);

  config::GraphConfig config_;
  ServiceOptions options_;
  EpisodeSource* source_;
  GraphSink* sink_;
  ProgressCallback on_progress_;
  Progress progress_;
  TrainingState state_;                  // the unfinished training, saved and restored whole
  std::optional<LearnedGraph> current_;  // last evaluated graph
  std::optional<LearnedGraph> published_;
  uint64_t next_version_ = 1;
  bool started_ = false;
  bool source_closed_ = false;
  int saved_episodes_ = 0;  // data set size at the last SaveTraining
  int action_entity_ = 0;
  // refinement (its ring and counters are in state_)
  int64_t refine_budget_ = 0;  // updates owed to episodes taken in
  bool refining_ = false;
  std::vector<double> action_correlation_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_report_, last_status_;
  // when the phase the last status reported began (for its ETA)
  Progress::Phase status_phase_ = Progress::Phase::kLoading;
  std::chrono::steady_clock::time_point status_phase_start_;
};

}  // namespace srics::graph_service
