#include "learner/sac.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "common/nn/serialize.h"
#include "learner/acting_policy.h"

namespace srics::learner {
namespace {

nn::ParameterList<float> Join(std::initializer_list<nn::ParameterList<float>> lists) {
  nn::ParameterList<float> all;
  for (const auto& l : lists) all.insert(all.end(), l.begin(), l.end());
  return all;
}

// Counters travel in a float section bit for bit (two 32-bit halves per counter).
std::vector<float> PackCounters(const LearnerCounters& c) {
  std::vector<float> out;
  for (uint64_t v : {c.updates, c.transitions_inserted, c.episodes_accepted, c.policy_version, c.training_env_steps}) {
    const uint32_t halves[2] = {static_cast<uint32_t>(v), static_cast<uint32_t>(v >> 32)};
    for (uint32_t h : halves) {
      float f;
      std::memcpy(&f, &h, sizeof f);
      out.push_back(f);
    }
  }
  return out;
}

LearnerCounters UnpackCounters(const std::vector<float>& values, const std::string& path) {
  constexpr int kCounters = 5;
  if (values.size() != 2 * kCounters) throw nn::CheckpointError(path + ": section 'counters' has the wrong size");
  uint64_t v[kCounters];
  for (int i = 0; i < kCounters; ++i) {
    uint32_t lo, hi;
    std::memcpy(&lo, &values[2 * i], sizeof lo);
    std::memcpy(&hi, &values[2 * i + 1], sizeof hi);
    v[i] = (static_cast<uint64_t>(hi) << 32) | lo;
  }
  return {v[0], v[1], v[2], v[3], v[4]};
}

}  // namespace

nn::CheckpointSection CountersSection(const LearnerCounters& counters) {
  return {"counters", "", PackCounters(counters), {}};
}

LearnerCounters CheckpointCounters(const std::vector<nn::CheckpointSection>& sections, const std::string& path) {
  return UnpackCounters(nn::FindSection(sections, "counters", path).values, path);
}

SacAgent::SacAgent(const AgentShape& shape, const config::AgentConfig& config, uint64_t seed, int threads)
    : shape_(shape),
      config_(config),
      net_config_(rl::MakeNetworkConfig(shape, config)),
      rng_(seed),
      policy_("policy", net_config_, rng_),
      q1_("q1", net_config_, rng_),
      q2_("q2", net_config_, rng_),
      q1_target_("q1_target", net_config_, rng_),
      q2_target_("q2_target", net_config_, rng_),
      log_alpha_("log_alpha", 1, 1),
      pool_(threads) {
  nn::SoftUpdate(q1_target_.Parameters(), q1_.Parameters(), 1.0);
  nn::SoftUpdate(q2_target_.Parameters(), q2_.Parameters(), 1.0);
  log_alpha_.value(0, 0) = static_cast<float>(std::log(config.sac.initial_alpha));
  policy_optimizer_ =
      std::make_unique<nn::Adam<float>>(policy_.Parameters(), nn::Adam<float>::Options{config.sac.policy_lr});
  q_optimizer_ = std::make_unique<nn::Adam<float>>(Join({q1_.Parameters(), q2_.Parameters()}),
                                                   nn::Adam<float>::Options{config.sac.q_lr});
  alpha_optimizer_ = std::make_unique<nn::Adam<float>>(nn::ParameterList<float>{&log_alpha_},
                                                       nn::Adam<float>::Options{config.sac.alpha_lr});
  const nn::ParameterList<float> trained = Join({policy_.Parameters(), q1_.Parameters(), q2_.Parameters()});
  for (int k = 1; k < threads; ++k) {
    shard_tapes_.push_back(std::make_unique<ShardTapes>());
    shard_grads_.push_back(std::make_unique<nn::GradientBuffer<float>>(trained));
    for (nn::Tape<float>* tape : shard_tapes_.back()->All()) tape->set_gradient_buffer(shard_grads_.back().get());
  }
}

nn::GemmPrecision SacAgent::SetProductPrecision(nn::GemmPrecision wanted) {
  precision_ = nn::EffectiveGemmPrecision(wanted);
  return precision_;
}

void SacAgent::ForEachShard(int batch, const std::function<void(ShardTapes&, int, int, int)>& part) {
  const int shards = std::min(pool_.size(), batch);
  pool_.Run([&](int k) {
    if (k >= shards) return;
    const nn::ScopedGemmPrecision precision(precision_);  // this shard's thread, for this pass
    const nn::ScopedSignalsHeld held;                     // once for the pass's products
    const auto [begin, end] = nn::PartRows(batch, shards, k);
    part(k == 0 ? tapes_ : *shard_tapes_[k - 1], k, begin, end);
  });
  for (int k = 1; k < shards; ++k) shard_grads_[k - 1]->AddInto();
}

void SacAgent::BoundTargets(float low, float high) {
  if (!(low <= high)) throw std::invalid_argument("SacAgent::BoundTargets: low > high");
  bounded_targets_ = true;
  target_low_ = low;
  target_high_ = high;
}

double SacAgent::alpha() const { return std::exp(static_cast<double>(log_alpha_.value(0, 0))); }

void SacAgent::LoadBatch(const TrainingBatch& b) {
  const int rows = b.size * b.max_entities;
  entities_ = Eigen::Map<const nn::Tensor>(b.entities.data(), rows, b.entity_dim);
  next_entities_ = Eigen::Map<const nn::Tensor>(b.next_entities.data(), rows, b.entity_dim);
  mask_ = Eigen::Map<const nn::Tensor>(b.mask.data(), b.size, b.max_entities);
  goals_ = Eigen::Map<const nn::Tensor>(b.goal.data(), b.size, b.goal_dim);
  actions_ = Eigen::Map<const nn::Tensor>(b.action.data(), b.size, b.action_dim);
  rewards_ = Eigen::Map<const nn::Tensor>(b.reward.data(), b.size, 1);
  if (b.terminal.empty())
    bootstraps_.setOnes(b.size, 1);
  else
    bootstraps_ = 1.0f - Eigen::Map<const nn::Tensor>(b.terminal.data(), b.size, 1).array();
}

UpdateStats SacAgent::Update(const TrainingBatch& batch) {
  LoadBatch(batch);
  const auto& sac = config_.sac;
  const int size = batch.size;
  const int ents = batch.max_entities;
  const float alpha = static_cast<float>(this->alpha());
  UpdateStats stats;
  stats.alpha = alpha;
  stats.mean_reward = rewards_.mean();
  // One shard is the whole batch (the one-thread path: no copies, no loss scaling). With
  // several, shard k sees rows [begin, end) of every batch matrix, and its loss is scaled by
  // its share of the batch so that the shards' gradients add up to the whole batch's.
  const bool whole = std::min(pool_.size(), size) == 1;
  auto rows = [&](const nn::Tensor& m, int begin, int end, int per_sample) -> nn::Tensor {
    return m.middleRows(static_cast<Eigen::Index>(begin) * per_sample,
                        static_cast<Eigen::Index>(end - begin) * per_sample);
  };
  auto share = [&](nn::Tape<float>& tape, nn::Var<float> loss, int begin, int end) {
    return whole ? loss : tape.MulScalar(loss, static_cast<float>(end - begin) / static_cast<float>(size));
  };
  const int shards = std::min(pool_.size(), size);
  std::vector<double> loss_part(static_cast<size_t>(shards)), sum_part(static_cast<size_t>(shards));
  auto total = [](const std::vector<double>& parts) {
    double t = 0;
    for (double p : parts) t += p;  // shard order: deterministic
    return t;
  };

  // bellman targets: y = scale * r + discount * (min target Q(s', a') - alpha log pi(a'|s'));
  // episodes end by time limit only, so every transition bootstraps unless the batch marks
  // it terminal (HAC). Then the critics. A shard's targets are its own rows, so each shard
  // goes from its targets to its critic gradients without waiting for the others.
  {
    const nn::Tensor noise = nn::RandomNormal<float>(size, shape_.action_dim, rng_);
    std::vector<char> targets_non_finite(static_cast<size_t>(shards), 0);
    q_optimizer_->ZeroGrad();
    ForEachShard(size, [&](ShardTapes& tapes, int k, int begin, int end) {
      nn::Tensor targets;
      {
        nn::Tape<float>& tape = tapes.targets;
        tape.Reset();
        auto ent = tape.Constant(whole ? next_entities_ : rows(next_entities_, begin, end, ents));
        auto mask = tape.Constant(whole ? mask_ : rows(mask_, begin, end, 1));
        auto goals = tape.Constant(whole ? goals_ : rows(goals_, begin, end, 1));
        auto next = policy_.Forward(tape, ent, mask, goals, whole ? noise : rows(noise, begin, end, 1), false);
        auto t1 = q1_target_.Forward(tape, ent, mask, goals, next.action, false);
        auto t2 = q2_target_.Forward(tape, ent, mask, goals, next.action, false);
        const auto r = rewards_.middleRows(begin, end - begin).array();
        const auto boot = bootstraps_.middleRows(begin, end - begin).array();
        targets = static_cast<float>(sac.reward_scale) * r +
                  static_cast<float>(sac.discount) * boot *
                      (t1.value().array().min(t2.value().array()) - alpha * next.log_prob.value().array());
      }
      if (!targets.allFinite()) {  // no critic step on non-finite targets (checked below)
        targets_non_finite[k] = 1;
        return;
      }
      if (bounded_targets_) targets = targets.cwiseMax(target_low_).cwiseMin(target_high_);
      nn::Tape<float>& tape = tapes.critics;
      tape.Reset();
      auto ent = tape.Constant(whole ? entities_ : rows(entities_, begin, end, ents));
      auto mask = tape.Constant(whole ? mask_ : rows(mask_, begin, end, 1));
      auto goals = tape.Constant(whole ? goals_ : rows(goals_, begin, end, 1));
      auto actions = tape.Constant(whole ? actions_ : rows(actions_, begin, end, 1));
      auto y = tape.Constant(targets);
      auto q1 = q1_.Forward(tape, ent, mask, goals, actions);
      auto q2 = q2_.Forward(tape, ent, mask, goals, actions);
      auto loss = share(
          tape, tape.Add(tape.Mean(tape.Square(tape.Sub(q1, y))), tape.Mean(tape.Square(tape.Sub(q2, y)))), begin, end);
      tape.Backward(loss);
      loss_part[k] = loss.value()(0, 0);
      sum_part[k] = whole ? q1.value().mean() : q1.value().sum();
    });
    if (sac.grad_clip_norm > 0) nn::ClipGradNorm(q_optimizer_->parameters(), sac.grad_clip_norm);
    if (std::find(targets_non_finite.begin(), targets_non_finite.end(), 1) != targets_non_finite.end()) {
      stats.non_finite = true;
      stats.non_finite_stage = "critic targets";
      return stats;
    }
    stats.q_loss = total(loss_part);
    stats.mean_q = whole ? sum_part[0] : total(sum_part) / size;
    if (!std::isfinite(stats.q_loss) || !nn::GradientsUsable(q_optimizer_->parameters())) {
      stats.non_finite = true;
      stats.non_finite_stage = "critic loss or gradient";
      return stats;
    }
    q_optimizer_->Step();
  }

  // policy: minimise alpha log pi - min Q over reparameterised actions (critics frozen)
  double mean_log_prob;
  {
    const nn::Tensor noise = nn::RandomNormal<float>(size, shape_.action_dim, rng_);
    policy_optimizer_->ZeroGrad();
    ForEachShard(size, [&](ShardTapes& tapes, int k, int begin, int end) {
      nn::Tape<float>& tape = tapes.policy;
      tape.Reset();
      auto ent = tape.Constant(whole ? entities_ : rows(entities_, begin, end, ents));
      auto mask = tape.Constant(whole ? mask_ : rows(mask_, begin, end, 1));
      auto goals = tape.Constant(whole ? goals_ : rows(goals_, begin, end, 1));
      auto pi = policy_.Forward(tape, ent, mask, goals, whole ? noise : rows(noise, begin, end, 1));
      auto q1 = q1_.Forward(tape, ent, mask, goals, pi.action, false);
      auto q2 = q2_.Forward(tape, ent, mask, goals, pi.action, false);
      auto loss = share(tape, tape.Mean(tape.Sub(tape.MulScalar(pi.log_prob, alpha), tape.Min(q1, q2))), begin, end);
      tape.Backward(loss);
      loss_part[k] = loss.value()(0, 0);
      sum_part[k] = whole ? pi.log_prob.value().mean() : pi.log_prob.value().sum();
    });
    if (sac.grad_clip_norm > 0) nn::ClipGradNorm(policy_optimizer_->parameters(), sac.grad_clip_norm);
    stats.policy_loss = total(loss_part);
    mean_log_prob = whole ? sum_part[0] : total(sum_part) / size;
    stats.entropy = -mean_log_prob;
    if (!std::isfinite(stats.policy_loss) || !std::isfinite(mean_log_prob) ||
        !nn::GradientsUsable(policy_optimizer_->parameters())) {
      stats.non_finite = true;
      stats.non_finite_stage = "policy loss or gradient";
      return stats;
    }
    policy_optimizer_->Step();
  }

  // temperature: loss = -log_alpha * (log pi + target entropy), gradient by hand
  if (sac.auto_entropy) {
    log_alpha_.grad(0, 0) = static_cast<float>(-(mean_log_prob + sac.target_entropy));
    alpha_optimizer_->Step();
  }

  nn::SoftUpdate(q1_target_.Parameters(), q1_.Parameters(), sac.tau);
  nn::SoftUpdate(q2_target_.Parameters(), q2_.Parameters(), sac.tau);
  return stats;
}

std::vector<float> SacAgent::PolicyWeights() { return nn::Flatten(policy_.Parameters()); }

std::string SacAgent::PolicySignature() { return rl::PolicySignature(policy_); }

void SacAgent::SaveCheckpoint(const std::string& path, const LearnerCounters& counters) {
  nn::WriteCheckpoint(path, CheckpointSections(counters));
}

LearnerCounters SacAgent::LoadCheckpoint(const std::string& path) {
  return LoadCheckpointSections(nn::ReadCheckpoint(path), path);
}

std::vector<nn::CheckpointSection> SacAgent::CheckpointSections(const LearnerCounters& counters) {
  auto section = [](const std::string& name, nn::ParameterList<float> params) {
    return nn::CheckpointSection{name, nn::SignatureString(params), nn::Flatten(params), {}};
  };
  return {
      section(kPolicySection, policy_.Parameters()),
      section("q1", q1_.Parameters()),
      section("q2", q2_.Parameters()),
      section("q1_target", q1_target_.Parameters()),
      section("q2_target", q2_target_.Parameters()),
      section("log_alpha", {&log_alpha_}),
      {"policy.adam", "", policy_optimizer_->ExportState(), {}},
      {"q.adam", "", q_optimizer_->ExportState(), {}},
      {"alpha.adam", "", alpha_optimizer_->ExportState(), {}},
      CountersSection(counters),
      {"agent.rng", "", {}, nn::RngState(rng_)},
  };
}

LearnerCounters SacAgent::LoadCheckpointSections(const std::vector<nn::CheckpointSection>& sections,
                                                 const std::string& path) {
  // check every part before changing anything, so a bad file leaves the agent as it was
  const std::pair<const char*, nn::ParameterList<float>> parts[] = {{kPolicySection, policy_.Parameters()},
                                                                    {"q1", q1_.Parameters()},
                                                                    {"q2", q2_.Parameters()},
                                                                    {"q1_target", q1_target_.Parameters()},
                                                                    {"q2_target", q2_target_.Parameters()},
                                                                    {"log_alpha", {&log_alpha_}}};
  for (const auto& [name, params] : parts) {
    const auto& s = nn::FindSection(sections, name, path);
    if (s.signature != nn::SignatureString(params))
      throw nn::CheckpointError(path + ": section '" + name + "': architecture mismatch");
  }
  const LearnerCounters counters = CheckpointCounters(sections, path);
  nn::Rng rng = rng_;
  for (const auto& s : sections)
    if (s.name == "agent.rng") nn::SetRngState(&rng, s.bytes, path + ": section 'agent.rng'");
  for (const auto& [name, params] : parts) nn::LoadSection(nn::FindSection(sections, name, path), params, path);
  rng_ = rng;
  try {
    policy_optimizer_->ImportState(nn::FindSection(sections, "policy.adam", path).values);
    q_optimizer_->ImportState(nn::FindSection(sections, "q.adam", path).values);
    alpha_optimizer_->ImportState(nn::FindSection(sections, "alpha.adam", path).values);
  } catch (const std::invalid_argument& e) {
    throw nn::CheckpointError(path + ": optimizer state: " + e.what());
  }
  return counters;
}

}  // namespace srics::learner
