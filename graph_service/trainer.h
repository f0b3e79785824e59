#pragma once
// Training of the GNN on a data set (RMSprop on windows with teacher forcing) and its
// evaluation: held-out loss and the mean edge weights over the whole data set.

#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "common/config/graph_config.h"
#include "common/nn/optim.h"
#include "common/nn/serialize.h"
#include "graph_service/dataset.h"
#include "graph_service/gnn_model.h"

namespace srics::graph_service {

// What an evaluation pass measured.
struct EdgeStatistics {
  int num_entities = 0;
  // mean_weight[i * N + j]: mean probability of the edge "i acts on j" over every step of
  // every episode of the data set (diagonal 0)
  std::vector<double> mean_weight;
  // refinement only: the same over every step of the run's training episodes (empty without)
  std::vector<double> training_mean_weight;
  // mean squared error of the position change per transition on the held-out episodes
  double held_out_mse = 0;
  // the same with a predicted change of zero (how much there is to predict)
  double held_out_zero_mse = 0;
  // per entity: held-out mean squared error of its position change (per axis), and the same
  // for a predicted change of zero
  std::vector<double> held_out_entity_mse, held_out_entity_zero_mse;
  // cut read-out (empty with the mean_weight read-out): cut_score[i * N + j] = held-out error
  // of j with the edge i -> j cut (its sender taken from another held-out episode) minus without, over what the model
  // explains of j (its no-motion error minus its error), clamped to [0, 1]; 0 into entities that do not move
  std::vector<double> cut_score;
  // apart_weight[i * N + j]: the mean edge probability over the random-action data's steps
  // where i and j are more than graph.contact_margin_m beyond touching, before and after the
  // step (0 where they never are). Empty unless object_edges is apart and the trainer has the entities' radii.
  std::vector<double> apart_weight;
  // whether the tie evidence was counted (GnnTrainer::tie_evidence_counted) and the object pairs
  // it names tied (GnnTrainer::tied_by_evidence): the read-out's calibration of object pairs
  bool tie_evidence_counted = false;
  std::vector<std::pair<int, int>> tied_by_evidence;
};

// Which entities move: the no-motion error of each (any scale) above `fraction` of the
// largest one's (config graph.static_variance_fraction).
std::vector<bool> MovingEntities(const std::vector<double>& no_motion_error, double fraction);

// Options of the model from the service config and a data set's shape.
GnnOptions MakeGnnOptions(const config::GraphConfig& config, const GraphDataset& data);

// Weight of the KL term at a given update: 0 during the warm-up (open edges), then a linear
// ramp to config.kl_weight.
double KlWeightAt(const config::GraphConfig& config, int64_t update);

// Thrown by GnnTrainer::Update when graph.max_skipped_updates_in_a_row updates in a row were
// skipped (non-finite loss or unusable gradient): the model no longer changes.
class GnnTrainingDivergedError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Owns the model and optimizer; single-threaded.
class GnnTrainer {
 public:
  // `data` must outlive the trainer and be split already.
  GnnTrainer(const config::GraphConfig& config, const GraphDataset& data, uint64_t seed);

  // Graph refinement: `share` of each batch's windows are drawn from `data` (the run's training
  // episodes, every episode in its training split), and evaluations average the edge weights
  // over its episodes too. null or a share of 0: none. `data` must outlive the trainer.
  void SetRefinementData(const GraphDataset* data, double share);
  // each graph entity's footprint bounding radius in metres (ServiceOptions::contact_radius),
  // for the apart weights of Evaluate and the onset weight's push and collision rules. The
  // onset weight applies only once every entity's radius is known (toy worlds have none)
  void SetContactRadii(std::vector<double> radii);
  // whether Evaluate scores object pairs apart (object_edges apart, radii of every entity)
  bool ApartWeights() const {
    return config_.object_edges == config::ObjectEdgeReadout::kApart &&
           contact_radius_.size() == static_cast<size_t>(data_.graph_entities());
  }

  // One RMSprop update on a fresh batch of windows; returns the batch's loss
  // (sum over the window of MSE + kl_weight * KL). A batch whose loss is not finite or whose
  // gradient is not usable (nn::GradientsUsable) changes no parameter and no optimiser state;
  // it still counts as an update (the schedule goes on) and as a skipped one, and NaN is
  // returned. Throws GnnTrainingDivergedError at graph.max_skipped_updates_in_a_row in a row.
  double Update();

  // Runs the model over whole episodes (all of them, in chunks) and returns the mean edge
  // weights and held-out error, and with the cut read-out the cut scores. Does not change the
  // parameters.
  EdgeStatistics Evaluate();

  // Cut scores of every edge (see EdgeStatistics::cut_score): N (N - 1) + 1 passes over the
  // held-out episodes with the same gate noise.
  std::vector<double> EdgeCutScores();
  // Held-out squared error per entity and transition (per axis), with the edge
  // cut_sender -> cut_receiver cut (-1: nothing cut).
  std::vector<double> HeldOutEntityError(int cut_sender, int cut_receiver);

  // The training state (parameters, both optimisers' moments, the batch stream, the update
  // count) as checkpoint sections, and back: a trainer that loads continues exactly where the
  // saved one was. LoadState throws nn::CheckpointError naming `path` and what does not fit
  // (another architecture, a missing section); the trainer may be partly changed then and
  // should be rebuilt.
  std::vector<nn::CheckpointSection> SaveState() const;
  void LoadState(const std::vector<nn::CheckpointSection>& sections, const std::string& path);

  // Graph refinement: the warm-up (every edge open) and the KL ramp start again from the next
  // update, so that every gate is decided anew on the data as it is now. A gate the KL has
  // closed is sampled open about edge_prior of the time and hardly learns otherwise.
  void RestartSchedule();
  // past the warm-up and the KL ramp of the current schedule: its graphs may count as stable
  bool Settled() const;

  int64_t updates() const { return updates_; }
  // skipped updates since this trainer was built (not checkpointed), and the current run of them
  int64_t skipped_updates() const { return skipped_updates_; }
  int64_t skipped_in_a_row() const { return skipped_in_a_row_; }
  double last_mse() const { return last_mse_; }  // per transition, last batch
  double last_kl() const { return last_kl_; }    // per transition, last batch
  GnnModel<float>& model() { return model_; }
  // Per graph entity, the onsets of motion in the whole data set (a step of more than
  // onset_motion_m after one below it) with every other entity out of reach throughout the step
  // (the onset weight's clearances: the arm's onsets never count): motion only a tie can start,
  // so the data's evidence of each tie, before any training. Zeros without the entities' radii
  // (SetContactRadii, which counts them on the data it finds).
  const std::vector<int64_t>& onsets_at_a_distance() const { return onsets_at_a_distance_; }
  // Those onsets by the object moving in the same step (more than onset_motion_m), per ordered
  // pair of graph entities: [i * N + j] counts j's onsets at a distance while i moves (i an
  // object; j's may count under several i). A tie's other end moves when it pulls; an untied
  // object's rare onsets at a distance coincide with another's motion only by chance.
  const std::vector<int64_t>& onsets_while_moving() const { return onsets_while_moving_; }
  // The object pairs (i < j, graph entities) whose both ends start moving at a distance at least
  // tie_evidence_per_episode times per episode of the data, at least tie_evidence_share of those
  // onsets while the other end moves: their edges pay tie_kl_factor times the KL (SetContactRadii
  // sets it) and the read-out keeps them above graph.tied_pair_threshold. Empty when not counted.
  const std::vector<std::pair<int, int>>& tied_by_evidence() const { return tied_by_evidence_; }
  // Whether the evidence was counted: tie_evidence_per_episode above 0, every entity's radius
  // (SetContactRadii) and a data set of one table (not combinations, whose samples order the
  // entities differently). Without it no pair counts as tied or untied by evidence.
  bool tie_evidence_counted() const { return tie_evidence_counted_; }
  // Logs the shapes of every matrix product of later updates (benchmark).
  void set_gemm_log(std::vector<nn::GemmShape>* log) { tape_.set_gemm_log(log); }

 private:
  config::GraphConfig config_;
  const GraphDataset& data_;
  nn::Rng rng_;
  GnnModel<float> model_;
  nn::ParameterList<float> params_;
  nn::RmsProp<float> optimizer_;
  nn::Adam<float> adam_;
  nn::Tape<float> tape_;
  WindowBatch<float> batch_, refine_batch_;
  const GraphDataset* refine_ = nullptr;
  std::vector<double> contact_radius_;
  // the onset weight's clearances (GnnModel::set_onset_clearance): the arm's onsets never
  // count; with a radius per graph entity, pushes and collisions do not either
  std::vector<double> OnsetClearance(const std::vector<double>& graph_radius) const;
  void CountOnsetsAtADistance();  // both counts; zeros without every radius
  bool Sized() const { return contact_radius_.size() == static_cast<size_t>(data_.graph_entities()); }
  std::vector<std::pair<int, int>> TiedByEvidence() const;  // from both counts
  std::vector<int64_t> onsets_at_a_distance_, onsets_while_moving_;
  std::vector<std::pair<int, int>> tied_by_evidence_;
  bool tie_evidence_counted_ = false;
  int arm_ = 0;  // SelectActionEntity of the data
  double refine_share_ = 0;
  int64_t updates_ = 0;
  int64_t schedule_start_ = 0;  // the update the warm-up / KL ramp schedule counts from
  double last_mse_ = 0, last_kl_ = 0;
  int64_t skipped_updates_ = 0, skipped_in_a_row_ = 0;
};

}  // namespace srics::graph_service
