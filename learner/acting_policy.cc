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

std::string ActingPoliciesBytes(rl::PolicyNetwork<float>& policy, rl::PolicyNetwork<float>* high,
                                const LearnerCounters& counters) {
  auto section = [](const std::string& name, const auto& params) {
    return nn::CheckpointSection{name, nn::SignatureString(params), nn::Flatten(params), {}};
  };
  std::vector<nn::CheckpointSection> sections = {section(kPolicySection, policy.Parameters())};
  if (high) sections.push_back(section(std::string(kHacHighPrefix) + kPolicySection, high->Parameters()));
  sections.push_back(CountersSection(counters));
  return nn::CheckpointBytes(sections);
}

}  // namespace srics::learner
