#pragma once
// Soft actor-critic on the goal-conditioned attention networks: twin Q functions with
// target copies, automatic entropy tuning, every hyperparameter from config::AgentConfig.
// One Update() is one gradient step of the critics, the policy and the temperature, then a
// soft target update (docs/method.md section 3).
//
// With threads > 1 (learner.threads) each of the two phases of an update (Bellman targets
// and critics; policy) splits the batch into one contiguous shard of samples per thread; each thread runs
// forward and backward on its shard with its own tape, the per-thread gradients are added in
// a fixed order, then one optimizer step: the same math as one thread up to the order of
// float summation, and deterministic for a given thread count. The random noise is drawn for
// the whole batch on the calling thread, as with one thread.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/config/agent_config.h"
#include "common/nn/gemm.h"
#include "common/nn/optim.h"
#include "common/nn/parallel.h"
#include "common/nn/serialize.h"
#include "common/nn/tape.h"
#include "common/rl/agent_shape.h"
#include "common/rl/networks.h"
#include "learner/relabeler.h"

namespace srics::learner {

using rl::AgentShape;

struct UpdateStats {
  double q_loss = 0;  // mean squared Bellman error, both critics summed
  double policy_loss = 0;
  double alpha = 0;
  double entropy = 0;  // -mean log pi
  double mean_q = 0;
  double mean_reward = 0;
  // a Bellman target, loss or gradient was not finite (or a gradient too large for Adam's
  // moments, |g| > 1e18): the stage where it showed and every
  // later one changed nothing (no optimizer step, no target update), so no NaN reaches a
  // network; the learner counts these updates
  bool non_finite = false;
  std::string non_finite_stage;  // where it showed: "critic targets", ... ("high level: ..." for HAC)
};

// Counters kept in checkpoints with the networks.
struct LearnerCounters {
  uint64_t updates = 0;
  uint64_t transitions_inserted = 0;
  uint64_t episodes_accepted = 0;
  uint64_t policy_version = 0;
  // env steps counted against the run's budget (for graph methods: from the graph's arrival)
  uint64_t training_env_steps = 0;
  bool operator==(const LearnerCounters&) const = default;
};

class SacAgent {
 public:
  // threads >= 1: threads that share each update (learner.threads).
  SacAgent(const AgentShape& shape, const config::AgentConfig& config, uint64_t seed, int threads);

  // One SAC update on a relabeled batch. A non-finite target, loss or gradient stops it
  // before that stage's optimizer step (UpdateStats::non_finite).
  UpdateStats Update(const TrainingBatch& batch);

  // The policy's parameters as one flat vector and its architecture signature: what
  // PolicyWeights carries to actors.
  std::vector<float> PolicyWeights();
  std::string PolicySignature();

  // Checkpoint: every network, target network, optimizer state, the temperature, the random
  // stream of the updates and the counters. Written atomically; Load throws
  // nn::CheckpointError naming what is wrong.
  void SaveCheckpoint(const std::string& path, const LearnerCounters& counters);
  LearnerCounters LoadCheckpoint(const std::string& path);
  // The same as sections, for a checkpoint file that holds more than the agent. Loading
  // checks every network's part before changing anything; a checkpoint without the random
  // stream (older ones) keeps the current one.
  std::vector<nn::CheckpointSection> CheckpointSections(const LearnerCounters& counters);
  LearnerCounters LoadCheckpointSections(const std::vector<nn::CheckpointSection>& sections, const std::string& path);

  // Clips every Bellman target into [low, high] from the next update on (HAC bounds each
  // level's Q to [-H, 0]); unbounded by default, as SAC is.
  void BoundTargets(float low, float high);
  // [low, high] when bounded
  std::optional<std::pair<float, float>> target_bounds() const {
    if (!bounded_targets_) return std::nullopt;
    return std::make_pair(target_low_, target_high_);
  }

  double alpha() const;
  // Logs the shape of every matrix product of the following updates (benchmarks; with
  // several threads only the calling thread's shard is logged).
  void set_gemm_log(std::vector<nn::GemmShape>* log) {
    for (nn::Tape<float>* tape : tapes_.All()) tape->set_gemm_log(log);
  }
  rl::PolicyNetwork<float>& policy() { return policy_; }
  rl::QNetwork<float>& q1() { return q1_; }
  rl::QNetwork<float>& q2() { return q2_; }
  const AgentShape& shape() const { return shape_; }
  int threads() const { return pool_.size(); }

  // The precision of the update's products (nn::GemmPrecision); kBf16 where the CPU lacks it
  // stays kFp32. Returns the one in effect.
  nn::GemmPrecision SetProductPrecision(nn::GemmPrecision wanted);
  nn::GemmPrecision product_precision() const { return precision_; }

 private:
  // One tape per pass of an update: a tape keeps its nodes' buffers from one pass to the next,
  // which is free only when the pass records the same ops with the same shapes every time. One
  // tape for all three passes reallocated most buffers twice per update; at batch 2048 those were
  // over the roles' 1 MiB mmap threshold of the time, so every pass paid page faults and munmaps:
  // ~30% of a batch-2048 run's CPU time (perf, 2026-12-06; process::SetUpHeap now).
  struct ShardTapes {
    nn::Tape<float> targets, critics, policy;
    std::array<nn::Tape<float>*, 3> All() { return {&targets, &critics, &policy}; }
  };
  void LoadBatch(const TrainingBatch& batch);
  // Runs part(tapes, k, begin, end) for each shard k of the batch's samples [begin, end),
  // shard 0 on the calling thread; the tapes of shard k > 0 write gradients into its own
  // buffer, which is added into Parameter::grad (shard order) when all are done.
  void ForEachShard(int batch, const std::function<void(ShardTapes&, int, int, int)>& part);

  AgentShape shape_;
  config::AgentConfig config_;
  rl::AttentionNetworkConfig net_config_;
  nn::Rng rng_;
  rl::PolicyNetwork<float> policy_;
  rl::QNetwork<float> q1_, q2_, q1_target_, q2_target_;
  nn::Parameter<float> log_alpha_;
  std::unique_ptr<nn::Adam<float>> policy_optimizer_, q_optimizer_, alpha_optimizer_;
  ShardTapes tapes_;
  nn::WorkerPool pool_;
  nn::GemmPrecision precision_ = nn::GemmPrecision::kFp32;
  // shards 1..threads-1: their tapes and gradient buffers (index k - 1)
  std::vector<std::unique_ptr<ShardTapes>> shard_tapes_;
  std::vector<std::unique_ptr<nn::GradientBuffer<float>>> shard_grads_;
  // the current batch as matrices
  nn::Tensor entities_, next_entities_, mask_, goals_, actions_, rewards_;
  nn::Tensor bootstraps_;  // B x 1: 0 for terminal transitions, else 1
  bool bounded_targets_ = false;
  float target_low_ = 0, target_high_ = 0;
};

}  // namespace srics::learner
