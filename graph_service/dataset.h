#pragma once
// The graph service's data: whole random-action episodes reduced to what the dynamics model
// needs (entity xy and actions), a deterministic train / held-out split, and batches of
// training windows (docs/method.md section 2).

#include <cstdint>
#include <string>
#include <vector>

#include "common/nn/serialize.h"
#include "common/nn/tensor.h"
#include "common/rl/episode.h"

namespace srics::graph_service {

// A batch of windows ready for the model: per transition t of the window, the node inputs
// and the position changes to predict. Row b * N + n is entity n of window b.
template <typename T>
struct WindowBatch {
  int batch = 0;                      // B windows
  int num_entities = 0;               // N
  std::vector<nn::Matrix<T>> inputs;  // per t: (B*N) x F, F = 2 + K + A: [x, y, kind, a]
  std::vector<nn::Matrix<T>> deltas;  // per t: (B*N) x 2, xy(t+1) - xy(t)
  int steps() const { return static_cast<int>(inputs.size()); }
};

// The shape every episode of a data set has.
struct DatasetShape {
  rl::EntityLayout layout;
  std::vector<uint16_t> entity_kinds;
  int action_dim = 0;
  // Training combinations (rl::EnvironmentShape::episode_kinds): when set, episodes present
  // one of these kind lists (all of one size) instead of `entity_kinds`, and the graph is over
  // the catalogue (`layout.num_kinds` entities).
  std::vector<std::vector<uint16_t>> episode_kinds;
};

// Episodes of one entity layout, stored as xy per entity and step plus actions.
//
// A data set of combinations holds episodes of several kind lists (training combinations of
// an environment with object_sets: the same N, different objects). Its graph entities are the
// catalogue's (entity e of episode ep is graph entity kinds[e]); with one kind list they are
// the episode's entities.
//
// Not thread-safe; the service owns it on one thread.
class GraphDataset {
 public:
  // All episodes must have this layout (N, K, velocities), these entity kinds, action size
  // and number of steps; others are refused by Add.
  GraphDataset(const rl::EntityLayout& layout, std::vector<uint16_t> entity_kinds, int action_dim, int episode_steps);
  // Episodes may have any one of `kind_sets` (each of N kinds, distinct, below K, at least one
  // set), and the graph is over the K catalogue entities (even with one set: an environment
  // whose object_sets has one combination still publishes the catalogue's graph).
  GraphDataset(const rl::EntityLayout& layout, std::vector<std::vector<uint16_t>> kind_sets, int action_dim,
               int episode_steps);
  // The data set a run's shape implies (one of the constructors above).
  static GraphDataset ForShape(const DatasetShape& shape, int episode_steps);
  // A data set of the same shape without episodes.
  GraphDataset EmptyCopy() const;

  // Makes a dataset shaped like `episode` (which is not added).
  static GraphDataset ShapedLike(const rl::Episode& episode);

  // A data set of the same shape for the run's training episodes (graph refinement): episodes
  // of `episode_steps` steps, explore or training mode, each in the training split as it is
  // added (no Split, no held-out side).
  GraphDataset ForTrainingEpisodes(int episode_steps) const;

  // Adds an episode; returns an empty string when accepted, else why it was refused (wrong
  // mode or shape, inconsistent sizes, non-finite values). Never throws on bad input.
  std::string Add(const rl::Episode& episode);
  // Puts `episode` in the place of episode `index` (the same checks as Add; it keeps the
  // place's side of the split); returns why it was refused, and nothing changes then.
  // Throws std::out_of_range for an index outside the data set.
  std::string Replace(int index, const rl::Episode& episode);

  // The episodes (not the split) as checkpoint bytes, and back. Load checks the bytes against
  // this data set's shape and throws nn::CheckpointError naming what differs; on a throw the
  // data set is unchanged. Only an empty data set can load.
  void Save(nn::ByteWriter& out) const;
  void Load(nn::ByteReader& in);

  // Fixes the split: the last round(fraction * size) episodes of a seeded shuffle are held
  // out. Call once all episodes are in; throws std::logic_error if a side would be empty.
  void Split(double held_out_fraction, uint64_t seed);

  int size() const { return static_cast<int>(actions_.size()); }
  const rl::EntityLayout& layout() const { return layout_; }
  int num_entities() const { return layout_.num_entities; }
  int num_kinds() const { return layout_.num_kinds; }
  int action_dim() const { return action_dim_; }
  int episode_steps() const { return steps_; }
  // input features per node: x, y, kind one-hot, action
  int input_dim() const { return 2 + layout_.num_kinds + action_dim_; }
  // the (first) kind list of the episodes
  const std::vector<uint16_t>& entity_kinds() const { return kind_sets_.front(); }
  const std::vector<std::vector<uint16_t>>& kind_sets() const { return kind_sets_; }
  // kinds of episode ep's entities
  const std::vector<uint16_t>& episode_kinds(int episode) const { return kind_sets_[set_of_[episode]]; }
  // the graph's entities: the catalogue for combinations, else the episodes' own
  bool combinations() const { return by_identity_; }
  int graph_entities() const { return combinations() ? layout_.num_kinds : layout_.num_entities; }
  int graph_entity(int episode, int entity) const { return combinations() ? episode_kinds(episode)[entity] : entity; }
  // kind of each graph entity
  std::vector<uint16_t> graph_kinds() const;
  const std::vector<int>& train_episodes() const { return train_; }
  const std::vector<int>& held_out_episodes() const { return held_out_; }

  // xy of `entity` at step t of episode e (t in 0..T).
  const float* position(int episode, int t, int entity) const {
    return positions_[episode].data() + (static_cast<size_t>(t) * num_entities() + entity) * 2;
  }
  // action taken at step t of episode e (t in 0..T-1).
  const float* action(int episode, int t) const {
    return actions_[episode].data() + static_cast<size_t>(t) * action_dim_;
  }

  // Fills `out` with `batch` windows of `window` transitions drawn uniformly (episode, start)
  // from the training split.
  template <typename T>
  void SampleWindows(int batch, int window, nn::Rng& rng, WindowBatch<T>* out) const;

  // Fills `out` with whole episodes (all T transitions) of the given ids.
  template <typename T>
  void EpisodeBatch(const std::vector<int>& episodes, WindowBatch<T>* out) const;

 private:
  template <typename T>
  void Fill(const std::vector<int>& episodes, const std::vector<int>& starts, int window, WindowBatch<T>* out) const;

  void CheckShape() const;  // throws std::invalid_argument naming what does not fit

  struct StoredEpisode {
    std::vector<float> positions, actions;
    uint8_t set = 0;
  };
  // Checks an episode against the data set and converts it; returns why it does not fit.
  std::string Convert(const rl::Episode& episode, StoredEpisode* out) const;

  rl::EntityLayout layout_;
  std::vector<std::vector<uint16_t>> kind_sets_;
  bool by_identity_;             // graph entities are catalogue kinds (the kind-lists constructor)
  std::vector<uint8_t> set_of_;  // per episode: index into kind_sets_
  int action_dim_;
  int steps_;
  std::vector<std::vector<float>> positions_;  // per episode (T+1) x N x 2
  std::vector<std::vector<float>> actions_;    // per episode T x A
  std::vector<int> train_, held_out_;
  bool training_episodes_ = false;  // ForTrainingEpisodes: training mode too, all in train_
};

// How strongly each entity's motion follows the action: the mean over action components of
// the largest absolute Pearson correlation between that component and the entity's x or y
// change, over every transition of the data set where it is present. Per graph entity.
std::vector<double> ActionCorrelations(const GraphDataset& data);

// The graph entity the action node attaches to: the one with the largest ActionCorrelations.
int SelectActionEntity(const GraphDataset& data);

}  // namespace srics::graph_service
