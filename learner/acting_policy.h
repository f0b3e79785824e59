#pragma once
// The acting networks of a learner checkpoint, for programs that only act (`srics eval`):
// the policy (and HAC's high-level policy) without the critics, optimizers or replay.

#include <string>
#include <vector>

#include "common/rl/networks.h"
#include "learner/sac.h"

namespace srics::learner {

// Section names of a learner checkpoint (sac.cc writes them; hac.cc prefixes the high level's).
inline constexpr const char* kPolicySection = "policy";
inline constexpr const char* kHacHighPrefix = "hac.high.";

// Loads the policy of checkpoint `path` into `policy`, and for HAC (`high` not null) the high
// level's policy into `high`; returns the checkpoint's counters (updates, policy version,
// training env steps). Throws nn::CheckpointError naming the file: cannot open, truncated,
// corrupted, another architecture (a network built from another config), no HAC sections.
LearnerCounters LoadActingPolicies(const std::string& path, rl::PolicyNetwork<float>& policy,
                                   rl::PolicyNetwork<float>* high);

// The counters section of a checkpoint's sections (sac.cc's layout). Throws nn::CheckpointError.
LearnerCounters CheckpointCounters(const std::vector<nn::CheckpointSection>& sections, const std::string& path);
// The counters as a checkpoint section (sac.cc's layout).
nn::CheckpointSection CountersSection(const LearnerCounters& counters);

// A file of the acting networks alone, in the learner checkpoint's format and section names
// (LoadActingPolicies and `srics eval` read it): the policy, HAC's high-level policy when
// `high` is not null, and the counters.
std::string ActingPoliciesBytes(rl::PolicyNetwork<float>& policy, rl::PolicyNetwork<float>* high,
                                const LearnerCounters& counters);

}  // namespace srics::learner
