#pragma once
// What the episode loops (explore, train, evaluation) share, internal to the actor library:
// reading the environment's states for the networks and the episode, stepping with a float
// action, and the full goal as a token.

#include <span>
#include <vector>

#include "actor/env/environment.h"
#include "common/nn/tensor.h"
#include "common/rl/episode.h"

namespace srics::actor {

// The rl view of the environment's current layout.
rl::EntityLayout LayoutOf(const env::Environment& env);

// Keeps the current entity states in both the float matrix the policy reads and the episode.
class Observer {
 public:
  explicit Observer(const env::Environment& env) : layout_(LayoutOf(env)) {}

  // Reads the environment's states into entities() (N x D).
  const nn::Tensor& Observe(const env::Environment& env);
  void Append(std::vector<float>* states) const {
    states->insert(states->end(), entities_.data(), entities_.data() + entities_.size());
  }
  const rl::EntityLayout& layout() const { return layout_; }
  const nn::Tensor& entities() const { return entities_; }

 private:
  rl::EntityLayout layout_;
  std::vector<double> buffer_;
  nn::Tensor entities_;
};

// An empty episode of this environment's layout, kinds and action size.
rl::Episode StartEpisode(const env::Environment& env, const rl::EntityLayout& layout);

// Steps with a float action (appended to *actions when given); false when the physics became
// unstable or the policy gave a non-finite action (weights that overflow: the environment
// would throw on it), so that the episode is dropped as unstable instead of ending the actor.
bool StepWith(env::Environment& env, const float* action, int dim, std::vector<float>* actions);

// The environment's full goal (every entity's xy) as a 1 x 2N token.
nn::Tensor FullGoalToken(const env::Environment& env);
// A goal of every entity's xy (2N floats) as a token of `goal_dim` floats (zero padded when
// the episode presents fewer entities than the networks take).
void WriteGoalToken(const float* xy, int num_entities, nn::Tensor* token, int goal_dim);
// The environment's full goal as a token for networks taking `goal_dim` floats.
nn::Tensor PaddedFullGoalToken(const env::Environment& env, int goal_dim);

}  // namespace srics::actor
