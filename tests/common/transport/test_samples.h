#pragma once
// Deterministic samples of every topic type, shared by the transport tests and the
// transport_peer helper process so both sides know what must arrive.

#include <cstdint>
#include <string>

#include "common/rl/episode.h"
#include "common/transport/endpoint.h"
#include "common/transport/wire.h"

namespace srics::transport::testing {

// A domain and run id of this test process alone, so tests running in parallel never see
// each other: the domain from ReserveDomain(20, 200), run id "<prefix>-<pid>".
config::TransportConfig IsolatedTransportConfig(const std::string& prefix);

// A domain in [first, first + count) that no other process calling this holds: an exclusive
// flock on /tmp/srics-test-domain-<id>.lock, kept until this process exits. The search starts
// at first + pid % count. The same range asked twice by one process gives the same domain.
// (A pid modulo alone let two security tests share a domain, and an open participant of one
// matched the other's "stranger".) Throws std::runtime_error when every domain is held.
int ReserveDomain(int first, int count);

// A whole train episode (`entities` of kSampleKinds kinds, 3 actions) within
// SampleEpisodeLimits(); `seed` varies ids and values.
inline constexpr int kSampleKinds = 8;
rl::Episode MakeEpisode(uint64_t seed, int steps = 20, int entities = 5);
// Episodes of up to kSampleKinds entities laid out as MakeEpisode's, no velocities.
rl::EpisodeLimits SampleEpisodeLimits();
// What a reader of such episodes is given.
ReaderOptions SampleEpisodeReader(const std::string& topic_name = "");

// A valid sample of run `run_id` (domain types: a writer stamps its participant's); `seed`
// varies every field (ids, sizes and values).
rl::WeightsUpdate MakePolicyWeights(uint64_t seed, size_t count = 1000);
rl::GraphUpdate MakeInteractionGraph(uint64_t seed);  // its structure not the adjacency's
rl::EvalReport MakeEvalResult(uint64_t seed);         // floats exact on the wire
rl::LearnerReport MakeLearnerStats(uint64_t seed);    // floats exact on the wire
rl::NodeStatus MakeNodeStatus(uint64_t seed);

// A well-formed graph of `entities` with every edge set, its true ancestor sets and depths
// (16 entities hung the learner and the actors before the entity count was checked first).
rl::GraphUpdate MakeCompleteGraph(int entities, uint64_t version);

}  // namespace srics::transport::testing
