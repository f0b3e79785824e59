#pragma once
// Deterministic samples of every topic type, shared by the transport tests and the
// transport_peer helper process so both sides know what must arrive.

#include <cstdint>
#include <string>

#include "common/transport/messages.h"

namespace srics::transport::testing {

// A valid sample of run `run_id`; `seed` varies every field (ids, sizes and values).
Episode MakeEpisode(const std::string& run_id, uint64_t seed, uint16_t steps = 20,
                    uint16_t entities = 5);
PolicyWeights MakePolicyWeights(const std::string& run_id, uint64_t seed, size_t count = 1000);
InteractionGraph MakeInteractionGraph(const std::string& run_id, uint64_t seed);
EvalResult MakeEvalResult(const std::string& run_id, uint64_t seed);
LearnerStats MakeLearnerStats(const std::string& run_id, uint64_t seed);
NodeStatus MakeNodeStatus(const std::string& run_id, uint64_t seed);

}  // namespace srics::transport::testing
