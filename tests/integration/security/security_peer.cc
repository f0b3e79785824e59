// The other process of the DDS Security tests: one participant with one identity of a
// keystore (or none), which tries to read or write a topic and says on stdout what happened
// (one line per event). Security is enforced between processes only (Cyclone connects
// endpoints of one process directly), so every identity under test runs in its own process.
//
//   security_peer DOMAIN RUN_ID KEYSTORE IDENTITY MODE [ARGS...]     (KEYSTORE "-": no security)
//     actor COUNT WAIT_S [SEED]  read the latest PolicyWeights ("weights V" or "no weights"),
//                          then write COUNT episodes MakeEpisode(SEED + i) (SEED 1000 by default;
//                          with identity actor-K they say actor K, as the run expects):
//                          "matched" or "no reader" (after WAIT_S), "wrote N"
//     actor-as K COUNT WAIT_S  write COUNT episodes, one EvalResult and one NodeStatus that all
//                          say actor K, through the library's writers (so in the identity's own
//                          partition): "matched" or "no reader", "wrote N"
//     write-in-partition P  create an episode writer in partition P with the C API ("refused"
//                          when DDS Security says no, else "created")
//     read-weights WAIT_S  "weights V" or "no weights"
//     write-weights SEED   create a PolicyWeights writer ("refused" when DDS Security says no),
//                          publish one sample and serve it until killed ("published")
//     write-stats SEED     the same for LearnerStats
// Exit codes: 0 ok, 2 usage, 6 exception, 7 refused by DDS Security.

#include <dds/dds.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <thread>

#include "common/transport/endpoint.h"
#include "common/transport/errors.h"
#include "srics.h"  // the generated C types (the topic descriptor)
#include "tests/common/transport/test_samples.h"

namespace {

using namespace srics::transport;
using namespace srics::transport::testing;
using std::chrono::milliseconds;
using std::chrono::seconds;

void Say(const std::string& line) { std::cout << line << std::endl; }

// Reads the latest weights for up to `wait`.
void ReadWeights(const Participant& participant, seconds wait) {
  Reader<srics::rl::WeightsUpdate> reader(participant);
  Say("ready");
  srics::rl::WeightsUpdate weights;
  if (reader.Take(&weights, wait) == TakeStatus::kSample)
    Say("weights " + std::to_string(weights.version));
  else
    Say("no weights");
}

// Publishes `msg` on a new writer and keeps it alive (transient-local) until killed.
template <typename T>
int PublishAndServe(const Participant& participant, const T& msg) {
  std::optional<Writer<T>> writer;
  try {
    writer.emplace(participant);
  } catch (const DdsError& e) {
    if (e.retcode() != DDS_RETCODE_NOT_ALLOWED_BY_SECURITY) throw;
    Say("refused");
    return 7;
  }
  if (writer->Write(msg) != WriteResult::kSent) {
    Say("not sent");
    return 5;
  }
  Say("published");
  while (!participant.shutdown_requested()) std::this_thread::sleep_for(milliseconds(50));
  return 0;
}

// K of identity "actor-K", or nothing.
std::optional<uint32_t> ActorIdOf(const std::string& identity) {
  if (identity.rfind("actor-", 0) != 0) return std::nullopt;
  return static_cast<uint32_t>(std::strtoul(identity.c_str() + 6, nullptr, 10));
}

// Episodes, an evaluation and a status that all say they come from actor `actor_id`.
int WriteAs(const Participant& participant, uint32_t actor_id, int count, seconds wait) {
  Writer<srics::rl::Episode> episodes(participant);
  Writer<srics::rl::EvalReport> evals(participant);
  Writer<srics::rl::NodeStatus> statuses(participant);
  Say(episodes.WaitForReaders(1, wait) && evals.WaitForReaders(1, wait) && statuses.WaitForReaders(1, wait)
          ? "matched"
          : "no reader");
  int sent = 0;
  for (int i = 0; i < count; ++i) {
    srics::rl::Episode episode = MakeEpisode(1000 + static_cast<uint64_t>(i));
    episode.actor_id = actor_id;
    if (episodes.TryWrite(episode) == WriteResult::kSent) ++sent;
  }
  srics::rl::EvalReport eval = MakeEvalResult(3);
  eval.actor_id = actor_id;
  srics::rl::NodeStatus status = MakeNodeStatus(4);
  status.role = "actor";
  status.node_id = actor_id;
  if (evals.Write(eval) != WriteResult::kSent || statuses.Write(status) != WriteResult::kSent) return 5;
  episodes.WaitForAcks(seconds(5));
  evals.WaitForAcks(seconds(5));
  statuses.WaitForAcks(seconds(5));
  Say("wrote " + std::to_string(sent));
  return 0;
}

// An episode writer in `partition`, made with Cyclone's C API (the library picks the partition
// itself): DDS Security's own check on this side.
int CreateWriterIn(const Participant& participant, const std::string& partition) {
  const dds_entity_t topic =
      dds_create_topic(participant.handle(), &srics_Episode_desc, "srics/episode", nullptr, nullptr);
  if (topic < 0) return 6;
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_partition1(qos, partition.c_str());
  const dds_entity_t writer = dds_create_writer(participant.handle(), topic, qos, nullptr);
  dds_delete_qos(qos);
  if (writer == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY) {
    Say("refused");
    return 7;
  }
  if (writer < 0) return 6;
  Say("created");
  return 0;
}

int Run(int argc, char** argv) {
  if (argc < 6) return 2;
  srics::config::TransportConfig config;
  config.domain_id = std::atoi(argv[1]);
  config.run_id = argv[2];
  if (std::string(argv[3]) != "-") config.security = {argv[3], argv[4]};
  const std::string mode = argv[5];
  Participant participant(config);
  Say("participant");
  if (mode == "actor" && (argc == 8 || argc == 9)) {
    const int count = std::atoi(argv[6]);
    const seconds wait(std::atoi(argv[7]));
    const uint64_t seed = argc == 9 ? std::strtoull(argv[8], nullptr, 10) : 1000;
    ReadWeights(participant, wait);
    Writer<srics::rl::Episode> writer(participant);
    Say(writer.WaitForReaders(1, wait) ? "matched" : "no reader");
    int sent = 0;
    const std::optional<uint32_t> own_id = ActorIdOf(config.security.identity);
    for (int i = 0; i < count; ++i) {
      srics::rl::Episode episode = MakeEpisode(seed + static_cast<uint64_t>(i));
      if (own_id) episode.actor_id = *own_id;
      // a writer without a matched reader "sends" into the void: count what DDS accepted
      if (writer.TryWrite(episode) == WriteResult::kSent) ++sent;
    }
    writer.WaitForAcks(seconds(5));
    Say("wrote " + std::to_string(sent));
    return 0;
  }
  if (mode == "actor-as" && argc == 9)
    return WriteAs(participant, static_cast<uint32_t>(std::atoi(argv[6])), std::atoi(argv[7]),
                   seconds(std::atoi(argv[8])));
  if (mode == "write-in-partition" && argc == 7) return CreateWriterIn(participant, argv[6]);
  if (mode == "read-weights" && argc == 7) {
    ReadWeights(participant, seconds(std::atoi(argv[6])));
    return 0;
  }
  if (mode == "write-weights" && argc == 7)
    return PublishAndServe(participant, MakePolicyWeights(std::strtoull(argv[6], nullptr, 10)));
  if (mode == "write-stats" && argc == 7)
    return PublishAndServe(participant, MakeLearnerStats(std::strtoull(argv[6], nullptr, 10)));
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const int code = Run(argc, argv);
    if (code == 2) std::cerr << "usage: security_peer DOMAIN RUN_ID KEYSTORE|- IDENTITY MODE [ARGS...]\n";
    return code;
  } catch (const std::exception& e) {
    Say(std::string("exception ") + e.what());
    return 6;
  }
}
