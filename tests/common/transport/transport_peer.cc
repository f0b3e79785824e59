// The other process of the transport tests: writes or reads the samples of test_samples.h
// over real DDS and reports on stdout (one line per event) and by exit code.
//
//   transport_peer MODE DOMAIN RUN_ID [ARGS...]
//     write TOPIC SEED        write one sample once a reader matched, wait for its ack
//     read TOPIC SEED         print "ready", take one sample, exit 0 if it equals the expected
//     count COUNT             print "ready", then "got ID" for each of COUNT episodes taken
//     latest                  publish graph and weights versions 1 then 2, print
//                             "published", serve them until SIGINT/SIGTERM
//     big COUNT               write one PolicyWeights of COUNT floats
//     episodes COUNT BLOCK_MS write COUNT episodes (ids 0..COUNT-1), print "backpressure N"
//     malformed               write broken episodes, then a good one (episode_id 7)
//     block                   print "ready", block in take until SIGINT, print "shutdown"
// Exit codes: 0 ok, 2 usage, 3 mismatch, 4 timeout, 5 unexpected result, 6 exception.

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>

#include "common/transport/endpoint.h"
#include "common/transport/errors.h"
#include "tests/common/transport/test_samples.h"

namespace {

using namespace srics::transport;
using namespace srics::transport::testing;
using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr auto kMatchTimeout = seconds(20);

void Say(const std::string& line) {
  std::cout << line << std::endl;  // flushed: the test waits for these lines
}

template <typename T>
int WriteOne(const Participant& participant, const T& msg) {
  Writer<T> writer(participant);
  if (!writer.WaitForReaders(1, kMatchTimeout)) return 4;
  if (writer.Write(msg) != WriteResult::kSent) return 5;
  return writer.WaitForAcks(kMatchTimeout) ? 0 : 4;
}

template <typename T>
int ReadOne(const Participant& participant, const T& expected) {
  Reader<T> reader(participant, SampleEpisodeReader());
  Say("ready");
  T got;
  if (reader.Take(&got, kMatchTimeout) != TakeStatus::kSample) return 4;
  if (!(got == expected)) {
    Say("mismatch");
    return 3;
  }
  Say("equal");
  return 0;
}

// Calls act(sample) with the seeded sample of the named topic; 2 for an unknown topic.
template <typename Act>
int WithSample(const std::string& run, const std::string& topic, uint64_t seed, Act act) {
  if (topic == "episode") return act(MakeEpisode(seed));
  if (topic == "policy_weights") return act(MakePolicyWeights(seed));
  if (topic == "interaction_graph") return act(MakeInteractionGraph(seed));
  if (topic == "eval_result") return act(MakeEvalResult(seed));
  if (topic == "learner_stats") return act(MakeLearnerStats(seed));
  if (topic == "node_status") return act(MakeNodeStatus(seed));
  return 2;
}

// Blocks in a take until shutdown; 0 when the take returned kShutdown.
int BlockUntilShutdown(const Participant& participant, milliseconds limit) {
  ReaderOptions options;
  options.topic_name = "srics/test/never_written";
  Reader<srics::rl::Episode> reader(participant, options);
  Say("ready");
  srics::rl::Episode unused;
  const TakeStatus status = reader.Take(&unused, limit);
  if (status != TakeStatus::kShutdown) return 5;
  Say("shutdown");
  return 0;
}

// Reports each episode as it arrives, so the test sees when it did.
int CountEpisodes(const Participant& participant, uint64_t count) {
  Reader<srics::rl::Episode> reader(participant, SampleEpisodeReader());
  Say("ready");
  for (uint64_t i = 0; i < count; ++i) {
    srics::rl::Episode got;
    if (reader.Take(&got, kMatchTimeout) != TakeStatus::kSample) return 4;
    Say("got " + std::to_string(got.episode_id));
  }
  return 0;
}

int Latest(const Participant& p) {
  Writer<srics::rl::GraphUpdate> graphs(p);
  Writer<srics::rl::WeightsUpdate> weights(p);
  for (uint64_t seed : {0, 1}) {
    if (graphs.Write(MakeInteractionGraph(seed)) != WriteResult::kSent) return 5;
    if (weights.Write(MakePolicyWeights(seed)) != WriteResult::kSent) return 5;
  }
  Say("published");
  return BlockUntilShutdown(p, seconds(60));
}

int Episodes(const Participant& p, uint64_t count) {
  Writer<srics::rl::Episode> writer(p);
  if (!writer.WaitForReaders(1, kMatchTimeout)) return 4;
  srics::rl::Episode episode = MakeEpisode(0);
  for (uint64_t id = 0; id < count; ++id) {
    episode.episode_id = id;
    if (writer.Write(episode) != WriteResult::kSent) return 5;
  }
  if (!writer.WaitForAcks(seconds(60))) return 4;
  Say("backpressure " + std::to_string(writer.back_pressure_count()));
  return 0;
}

// Episodes the readers must refuse, then a good one (episode_id 7). Raw writers: no checks,
// and one stamps an old contract version; another run's episode comes from a second
// participant.
int Malformed(const Participant& p) {
  using srics::rl::Episode;
  WriterOptions options;
  options.validate = false;
  Writer<Episode> raw(p, options);
  options.contract_version = kContractVersion - 1;
  Writer<Episode> old_contract(p, options);
  srics::config::TransportConfig other_config = p.config();
  other_config.run_id = p.run_id() + "-other";
  Participant other(other_config);
  options.contract_version = kContractVersion;
  Writer<Episode> other_run(other, options);
  for (Writer<Episode>* w : {&raw, &old_contract, &other_run})
    if (!w->WaitForReaders(1, kMatchTimeout)) return 4;
  const Episode good = MakeEpisode(7);
  Episode short_states = good;
  short_states.states.pop_back();
  Episode nan_state = good;
  nan_state.states[10] = std::numeric_limits<float>::quiet_NaN();
  Episode bad_actions = good;
  bad_actions.actions.push_back(0.5f);
  Episode far_away = good;  // finite but 1 km away: would poison the networks
  far_away.states[8] = 1000.0f;
  for (const Episode* e : {&short_states, &nan_state, &bad_actions, &far_away})
    if (raw.Write(*e) != WriteResult::kSent) return 5;
  if (old_contract.Write(good) != WriteResult::kSent || !old_contract.WaitForAcks(kMatchTimeout)) return 5;
  if (other_run.Write(good) != WriteResult::kSent || !other_run.WaitForAcks(kMatchTimeout)) return 5;
  if (raw.Write(good) != WriteResult::kSent) return 5;
  return raw.WaitForAcks(kMatchTimeout) ? 0 : 4;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: transport_peer MODE DOMAIN RUN_ID [ARGS...]\n";
    return 2;
  }
  const std::string mode = argv[1];
  srics::config::TransportConfig config;
  config.domain_id = std::atoi(argv[2]);
  config.run_id = argv[3];
  try {
    if (mode == "block" || mode == "latest") Shutdown::InstallSignalHandlers();
    if (mode == "episodes" && argc == 6) config.writer_max_blocking_ms = std::atoi(argv[5]);
    Participant participant(config);
    if (mode == "write" && argc == 6)
      return WithSample(participant.run_id(), argv[4], std::stoull(argv[5]),
                        [&](const auto& sample) { return WriteOne(participant, sample); });
    if (mode == "read" && argc == 6)
      return WithSample(participant.run_id(), argv[4], std::stoull(argv[5]),
                        [&](const auto& sample) { return ReadOne(participant, sample); });
    if (mode == "latest") return Latest(participant);
    if (mode == "count" && argc == 5) return CountEpisodes(participant, std::stoull(argv[4]));
    if (mode == "big" && argc == 5) return WriteOne(participant, MakePolicyWeights(5, std::stoull(argv[4])));
    if (mode == "episodes" && argc == 6) return Episodes(participant, std::stoull(argv[4]));
    if (mode == "malformed") return Malformed(participant);
    if (mode == "block") return BlockUntilShutdown(participant, seconds(60));
  } catch (const std::exception& e) {
    std::cerr << "transport_peer: " << e.what() << "\n";
    return 6;
  }
  std::cerr << "transport_peer: bad arguments for mode " << mode << "\n";
  return 2;
}
