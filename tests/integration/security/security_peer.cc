// The other process of the DDS Security tests: one participant with one identity of a
// keystore (or none), which tries to read or write a topic and says on stdout what happened
// (one line per event). Security is enforced between processes only (Cyclone connects
// endpoints of one process directly), so every identity under test runs in its own process.
//
//   security_peer DOMAIN RUN_ID KEYSTORE IDENTITY MODE [ARGS...]     (KEYSTORE "-": no security)
//     actor COUNT WAIT_S [SEED]  read the latest PolicyWeights ("weights V" or "no weights"),
//                          then write COUNT episodes MakeEpisode(SEED + i) (SEED 1000 by default):
//                          "matched" or "no reader" (after WAIT_S), "wrote N"
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
#include "tests/common/transport/test_samples.h"

namespace {

using namespace srics::transport;
using namespace srics::transport::testing;
using std::chrono::milliseconds;
using std::chrono::seconds;

void Say(const std::string& line) { std::cout << line << std::endl; }

// Reads the latest weights for up to `wait`.
void ReadWeights(const Participant& participant, seconds wait) {
  Reader<PolicyWeights> reader(participant);
  Say("ready");
  PolicyWeights weights;
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
    for (int i = 0; i < count; ++i) {
      srics::rl::Episode episode = MakeEpisode(seed + static_cast<uint64_t>(i));
      // a writer without a matched reader "sends" into the void: count what DDS accepted
      if (writer.TryWrite(episode) == WriteResult::kSent) ++sent;
    }
    writer.WaitForAcks(seconds(5));
    Say("wrote " + std::to_string(sent));
    return 0;
  }
  if (mode == "read-weights" && argc == 7) {
    ReadWeights(participant, seconds(std::atoi(argv[6])));
    return 0;
  }
  if (mode == "write-weights" && argc == 7)
    return PublishAndServe(participant, MakePolicyWeights(config.run_id, std::strtoull(argv[6], nullptr, 10)));
  if (mode == "write-stats" && argc == 7)
    return PublishAndServe(participant, MakeLearnerStats(config.run_id, std::strtoull(argv[6], nullptr, 10)));
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const int code = Run(argc, argv);
    if (code == 2)
      std::cerr << "usage: security_peer DOMAIN RUN_ID KEYSTORE|- IDENTITY MODE [ARGS...]\n";
    return code;
  } catch (const std::exception& e) {
    Say(std::string("exception ") + e.what());
    return 6;
  }
}
