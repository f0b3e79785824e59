#include "learner/acting_policy.h"

#include "common/nn/serialize.h"

namespace srics::learner {

LearnerCounters LoadActingPolicies(const std::string& path, rl::PolicyNetwork<float>& policy,
                                   rl::PolicyNetwork<float>* high) {
  const std::vector<nn::CheckpointSection> sections = nn::ReadCheckpoint(path);
  const LearnerCounters counters = CheckpointCounters(sections, path);
  nn::LoadSection(nn::FindSection(sections, kPolicySection, path), policy.Parameters(), path);
  if (high)
    nn::LoadSection(nn::FindSection(sections, std::string(kHacHighPrefix) + kPolicySection, path), high->Parameters(),
                    path);
  return counters;
}

}  // namespace srics::learner
