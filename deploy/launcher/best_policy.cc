#include "deploy/launcher/best_policy.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <spdlog/spdlog.h>

#include "actor/actor_loop.h"
#include "common/files/durable_file.h"
#include "common/files/small_file.h"
#include "common/nn/serialize.h"
#include "common/rl/agent_shape.h"
#include "learner/acting_policy.h"

namespace srics::launcher {

// The acting networks of the run, filled from kept weights when an evaluation wins.
struct BestPolicy::Networks {
  explicit Networks(const config::Config& config) {
    const actor::ActorOptions actor = actor::ActorOptionsFor(config, rl::RunShapeFor(config), 0);
    nn::Rng init(0);
    policy = std::make_unique<rl::PolicyNetwork<float>>("policy", actor.policy, init);
    if (actor.high_policy) high = std::make_unique<rl::PolicyNetwork<float>>("policy", *actor.high_policy, init);
    signature = high ? rl::HacPolicySignature(*high, *policy) : rl::PolicySignature(*policy);
    size = nn::NumScalars(policy->Parameters()) + (high ? nn::NumScalars(high->Parameters()) : 0);
  }
  std::unique_ptr<rl::PolicyNetwork<float>> policy, high;
  std::string signature;
  int64_t size = 0;
};

std::string BestEvaluationYaml(const BestEvaluation& best) {
  char text[512];
  std::snprintf(text, sizeof text,
                "# the evaluation whose policy best.srics holds: the lowest average distance so far\n"
                "policy_version: %llu\nupdate_count: %llu\nenv_steps: %llu\navg_distance: %.9g\n",
                static_cast<unsigned long long>(best.policy_version),
                static_cast<unsigned long long>(best.update_count), static_cast<unsigned long long>(best.env_steps),
                best.avg_distance);
  return text;
}

std::optional<BestEvaluation> ParseBestEvaluation(const std::string& text) {
  BestEvaluation best;
  int found = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const size_t colon = line.find(':');
    if (line.empty() || line[0] == '#' || colon == std::string::npos) continue;
    const std::string key = line.substr(0, colon), value = line.substr(colon + 1);
    char* end = nullptr;
    if (key == "avg_distance") {
      best.avg_distance = std::strtod(value.c_str(), &end);
      if (end == value.c_str() || !std::isfinite(best.avg_distance)) return std::nullopt;
      ++found;
      continue;
    }
    uint64_t* field = key == "policy_version" ? &best.policy_version
                      : key == "update_count" ? &best.update_count
                      : key == "env_steps"    ? &best.env_steps
                                              : nullptr;
    if (field == nullptr) continue;
    *field = std::strtoull(value.c_str(), &end, 10);
    if (end == value.c_str()) return std::nullopt;
    ++found;
  }
  if (found != 4) return std::nullopt;
  return best;
}

BestPolicy::BestPolicy(const config::Config& config, std::string dir, size_t kept_bytes)
    : dir_(std::move(dir)), networks_(std::make_unique<Networks>(config)), kept_bytes_limit_(kept_bytes) {
  // a resumed run: only a better evaluation replaces the best so far
  if (std::ifstream(dir_ + "/best.yaml") && std::ifstream(dir_ + "/best.srics"))
    best_ = ParseBestEvaluation(files::ReadSmallFile(dir_ + "/best.yaml"));  // throws over the size limit
}

BestPolicy::~BestPolicy() = default;

void BestPolicy::OnWeights(uint64_t version, uint64_t update_count, const std::string& architecture,
                           const std::vector<float>& parameters) {
  // weights of another network (a foreign run's, a bad sample) are not this run's policy
  if (architecture != networks_->signature || static_cast<int64_t>(parameters.size()) != networks_->size) return;
  if (!kept_.empty() && kept_.back().version >= version) return;  // a repeat (transient-local)
  kept_.push_back({version, update_count, parameters});
  kept_bytes_ += parameters.size() * sizeof(float);
  while (kept_.size() > kMinKeptVersions && kept_bytes_ > kept_bytes_limit_) {
    kept_bytes_ -= kept_.front().parameters.size() * sizeof(float);
    kept_.pop_front();
  }
}

std::optional<BestEvaluation> BestPolicy::OnEval(uint64_t policy_version, uint64_t env_steps, double avg_distance) {
  if (policy_version == 0 || !std::isfinite(avg_distance)) return std::nullopt;  // the passive policy
  if (best_ && avg_distance >= best_->avg_distance) return std::nullopt;
  const Kept* kept = nullptr;
  for (const Kept& k : kept_)
    if (k.version == policy_version) kept = &k;
  if (kept == nullptr) {
    spdlog::warn(
        "evaluation of policy v{} (avg distance {:.4f}) is the best so far, but its weights are no longer "
        "kept: best.srics not updated",
        policy_version, avg_distance);
    return std::nullopt;
  }
  // the weights into the networks (HAC: the high level's parameters first, as published)
  const std::span<const float> flat(kept->parameters);
  const int64_t high_size = networks_->high ? nn::NumScalars(networks_->high->Parameters()) : 0;
  if (networks_->high) nn::LoadFlat(networks_->high->Parameters(), flat.first(high_size));
  nn::LoadFlat(networks_->policy->Parameters(), flat.subspan(high_size));
  learner::LearnerCounters counters;
  counters.updates = kept->update_count;
  counters.policy_version = kept->version;
  counters.training_env_steps = env_steps;
  const BestEvaluation best{kept->version, kept->update_count, env_steps, avg_distance};
  files::WriteFileDurably(dir_ + "/best.srics",
                          learner::ActingPoliciesBytes(*networks_->policy, networks_->high.get(), counters));
  files::WriteFileDurably(dir_ + "/best.yaml", BestEvaluationYaml(best));
  best_ = best;
  return best;
}

}  // namespace srics::launcher
