#pragma once
// HAC's two levels acting on one full goal (Levy et al., ICLR 2019; docs/method.md): the high
// level proposes a subgoal (the xy of every entity) whenever the previous one is over, the low
// level acts towards it. Shared by HAC's training and evaluation episodes.

#include <vector>

#include "common/nn/tensor.h"
#include "common/rl/episode.h"
#include "common/rl/hac.h"
#include "common/rl/networks.h"

namespace srics::actor {

// How HAC's two levels act (agent.hac; the subgoal box from the table).
struct HacActOptions {
  int horizon = 20;               // H: low steps per subgoal at most, subgoals per training episode
  double test_probability = 0.3;  // a subgoal is tested (the low level acts without noise)
  double threshold = 0.05;        // a goal is reached with every entity this close
  rl::SubgoalBox box;
};

class HacActor {
 public:
  // `full_goal` (a token for the high level) must outlive the actor.
  HacActor(rl::PolicyNetwork<float>& high, rl::PolicyNetwork<float>& low, const HacActOptions& options,
           const rl::EntityLayout& layout, const nn::Tensor& full_goal)
      : high_(high),
        low_(low),
        options_(options),
        layout_(layout),
        full_goal_(full_goal),
        subgoal_(2 * layout.num_entities) {}

  // True when the high level has to propose the next subgoal before the low level acts in
  // state `entities`: none yet, held H steps, reached, or the full goal reached.
  bool SubgoalOver(const nn::Tensor& entities) const;
  // The high level's proposal in state `entities`; `test`: the low level then acts without noise.
  const std::vector<float>& Propose(const nn::Tensor& entities, bool deterministic, bool test, nn::Rng& rng);
  // The low level's action towards the current subgoal.
  const nn::Tensor& Act(const nn::Tensor& entities, bool deterministic, nn::Rng& rng);

 private:
  rl::PolicyNetwork<float>& high_;
  rl::PolicyNetwork<float>& low_;
  const HacActOptions& options_;
  rl::EntityLayout layout_;
  const nn::Tensor& full_goal_;
  std::vector<float> subgoal_;
  nn::Tensor subgoal_token_;
  int held_ = -1;  // steps the current subgoal was held; -1: none yet
  bool test_ = false;
};

}  // namespace srics::actor
