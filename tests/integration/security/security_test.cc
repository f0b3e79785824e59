// DDS Security (issue 15): a keystore made by deploy/security/make-keystore.sh in the test's
// temporary folder, the participant of this process with one identity and every other
// identity (or none) in a security_peer process of its own: Cyclone connects the endpoints of
// one process directly, without the security plugins, so only processes test the access rules.

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <linux/if_ether.h>
#include <linux/if_packet.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/config/config.h"
#include "common/config/config_error.h"
#include "common/transport/endpoint.h"
#include "common/transport/errors.h"
#include "tests/common/transport/peer_process.h"
#include "tests/common/transport/test_samples.h"

namespace srics::transport {
namespace {

using namespace std::chrono_literals;
using testing::PeerProcess;

namespace fs = std::filesystem;

// The keystore of every test here: made once (about 2 s of openssl).
class SecurityTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    keystore_ = new std::string(fs::temp_directory_path() / ("srics-keystore-" + std::to_string(getpid())));
    fs::remove_all(*keystore_);
    const std::string command = std::string(SRICS_SOURCE_DIR) + "/deploy/security/make-keystore.sh " + *keystore_ +
                                " --actors 2 > " + *keystore_ + ".log 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*keystore_);
    fs::remove(*keystore_ + ".log");
    delete keystore_;
  }

  // This process's transport with `identity` of the keystore, on a domain no other test
  // process holds (220..229: other tests use 20..219; DDS Security takes domains up to 230).
  config::TransportConfig Secured(const std::string& identity) const {
    config::TransportConfig c = testing::IsolatedTransportConfig("security");
    c.domain_id = testing::ReserveDomain(220, 10);
    c.security = {*keystore_, identity};
    return c;
  }

  // security_peer with `identity` ("" = no credentials at all) on this test's domain and run.
  std::unique_ptr<PeerProcess> Peer(const std::string& identity, const std::vector<std::string>& mode) const {
    const config::TransportConfig c = Secured(identity);
    std::vector<std::string> args = {std::to_string(c.domain_id), c.run_id, identity.empty() ? "-" : *keystore_,
                                     identity.empty() ? "-" : identity};
    args.insert(args.end(), mode.begin(), mode.end());
    return std::make_unique<PeerProcess>(SRICS_SECURITY_PEER, args);
  }

  static std::string* keystore_;

 public:
  static const std::string& Keystore() { return *keystore_; }
};

std::string* SecurityTest::keystore_ = nullptr;

// A fresh copy of the test keystore at its path + `suffix`, for a test that alters it.
std::string CopyOfKeystore(const std::string& suffix) {
  const std::string copy = SecurityTest::Keystore() + suffix;
  fs::remove_all(copy);
  fs::copy(SecurityTest::Keystore(), copy, fs::copy_options::recursive);
  return copy;
}

// The whole text of a file ("" when it cannot be read).
std::string ReadText(const std::string& path) {
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  return text.str();
}

// The exit code of a shell command (-1 when it did not exit: a signal ended it).
int ExitCodeOf(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Reads the peer's lines until one equals `expected`; the lines seen otherwise.
::testing::AssertionResult SaysLine(PeerProcess& peer, const std::string& expected,
                                    std::chrono::milliseconds timeout = 60s) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::string seen;
  while (std::chrono::steady_clock::now() < deadline) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    const auto line = peer.ReadLine(left);
    if (!line) break;
    if (*line == expected) return ::testing::AssertionSuccess();
    seen += " [" + *line + "]";
  }
  return ::testing::AssertionFailure() << "expected '" << expected << "', the peer said:" << seen;
}

// Takes episodes until `count` arrived or `timeout` passed; how many arrived.
size_t TakeEpisodes(Reader<rl::Episode>& reader, size_t count, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  size_t taken = 0;
  rl::Episode episode;
  while (taken < count && std::chrono::steady_clock::now() < deadline)
    if (reader.Take(&episode, 200ms) == TakeStatus::kSample) ++taken;
  return taken;
}

// Every frame on the loopback interface while it lives (an AF_PACKET socket: needs
// CAP_NET_RAW, i.e. root). Other tests' traffic is captured too; callers look for their own bytes.
class LoopbackCapture {
 public:
  // nullptr when this process may not capture.
  static std::unique_ptr<LoopbackCapture> Start() {
    const int fd = socket(AF_PACKET, SOCK_RAW, htons(ETH_P_ALL));
    if (fd < 0) return nullptr;
    const int buffer = 64 << 20;
    setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &buffer, sizeof buffer);
    sockaddr_ll address{};
    address.sll_family = AF_PACKET;
    address.sll_protocol = htons(ETH_P_ALL);
    address.sll_ifindex = static_cast<int>(if_nametoindex("lo"));
    if (bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
      close(fd);
      return nullptr;
    }
    return std::unique_ptr<LoopbackCapture>(new LoopbackCapture(fd));
  }
  ~LoopbackCapture() {
    stop_ = true;
    thread_.join();
    close(fd_);
  }
  // Whether `bytes` occurred in a frame so far.
  bool Saw(const std::string& bytes) {
    std::lock_guard lock(mutex_);
    return std::search(frames_.begin(), frames_.end(), bytes.begin(), bytes.end()) != frames_.end();
  }

 private:
  explicit LoopbackCapture(int fd) : fd_(fd), thread_([this] { Run(); }) {}
  void Run() {
    std::vector<char> frame(1 << 17);
    while (!stop_) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 50) <= 0) continue;
      const ssize_t n = recv(fd_, frame.data(), frame.size(), 0);
      std::lock_guard lock(mutex_);
      if (n > 0 && frames_.size() < (512u << 20)) frames_.append(frame.data(), static_cast<size_t>(n)).push_back('\0');
    }
  }
  int fd_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::string frames_;
  std::thread thread_;
};

// The bytes of floats [from, from + count) as they travel (XCDR, little-endian floats).
std::string BytesOf(const std::vector<float>& values, size_t from, size_t count) {
  return std::string(reinterpret_cast<const char*>(values.data() + from), count * sizeof(float));
}

// The learner's end of the exchanges below, in this process: it writes weights and reads
// episodes.
struct LearnerSide {
  explicit LearnerSide(const config::TransportConfig& transport)
      : participant(transport), weights(participant), episodes(participant, testing::SampleEpisodeReader()) {}
  Participant participant;
  Writer<rl::WeightsUpdate> weights;
  Reader<rl::Episode> episodes;
};

// Two identities of the keystore in two processes: the actor reads the learner's weights
// (transient-local, through authentication, key exchange and encryption) and its episodes
// reach the learner; the read-only monitor identity reads the weights as well.
TEST_F(SecurityTest, SecuredProcessesExchangeWeightsAndEpisodes) {
  LearnerSide learner(Secured("learner"));
  const rl::WeightsUpdate published = testing::MakePolicyWeights(5);
  ASSERT_EQ(learner.weights.Write(published), WriteResult::kSent);
  const std::string got_weights = "weights " + std::to_string(published.version);

  auto actor = Peer("actor-0", {"actor", "4", "60"});
  EXPECT_TRUE(SaysLine(*actor, got_weights));
  EXPECT_TRUE(SaysLine(*actor, "matched"));
  EXPECT_TRUE(SaysLine(*actor, "wrote 4"));
  EXPECT_EQ(TakeEpisodes(learner.episodes, 4, 30s), 4u);
  EXPECT_EQ(learner.participant.counters(TopicId::kEpisode).accepted, 4u);
  EXPECT_EQ(actor->Wait(30s), 0);

  auto monitor = Peer("monitor", {"read-weights", "60"});
  EXPECT_TRUE(SaysLine(*monitor, got_weights));
  EXPECT_EQ(monitor->Wait(30s), 0);
}

// A participant without credentials on the same domain: it discovers no writer (no weights
// arrive), no reader matches its episode writer, and the learner receives nothing from it,
// not even a sample to reject (every counter stays 0). An actor with credentials, after it,
// shows the learner was listening all along.
TEST_F(SecurityTest, ParticipantWithoutCredentialsSeesNothingAndCannotInject) {
  LearnerSide learner(Secured("learner"));
  const rl::WeightsUpdate published = testing::MakePolicyWeights(8);
  ASSERT_EQ(learner.weights.Write(published), WriteResult::kSent);

  auto stranger = Peer("", {"actor", "20", "8"});
  EXPECT_TRUE(SaysLine(*stranger, "no weights"));
  EXPECT_TRUE(SaysLine(*stranger, "no reader"));
  EXPECT_TRUE(SaysLine(*stranger, "wrote 20"));  // into the void
  EXPECT_EQ(stranger->Wait(30s), 0);
  EXPECT_EQ(TakeEpisodes(learner.episodes, 1, 3s), 0u);
  const SampleCounters counters = learner.participant.counters(TopicId::kEpisode);
  EXPECT_EQ(counters.accepted, 0u);
  EXPECT_EQ(counters.rejected, 0u);
  EXPECT_EQ(counters.other_run, 0u);
  EXPECT_EQ(learner.participant.total_rejected(), 0u);

  auto actor = Peer("actor-1", {"actor", "2", "60"});
  EXPECT_TRUE(SaysLine(*actor, "weights " + std::to_string(published.version)));
  EXPECT_TRUE(SaysLine(*actor, "matched"));
  EXPECT_EQ(TakeEpisodes(learner.episodes, 2, 30s), 2u);
  EXPECT_EQ(learner.participant.counters(TopicId::kEpisode).accepted, 2u);
}

// Only the learner publishes PolicyWeights and LearnerStats: the read-only monitor identity
// and an actor identity are refused a writer by DDS Security, and nothing of theirs reaches
// an actor's readers; the learner identity's weights do.
TEST_F(SecurityTest, MonitorAndActorIdentitiesCannotPublishWeightsOrStats) {
  Participant actor(Secured("actor-0"));
  Reader<srics::rl::WeightsUpdate> weights(actor);
  Reader<srics::rl::LearnerReport> stats(actor);
  for (const auto& [identity, mode] : std::vector<std::pair<std::string, std::string>>{{"monitor", "write-weights"},
                                                                                       {"monitor", "write-stats"},
                                                                                       {"actor-1", "write-weights"},
                                                                                       {"actor-1", "write-stats"}}) {
    SCOPED_TRACE(identity + " " + mode);
    auto peer = Peer(identity, {mode, "9"});
    EXPECT_TRUE(SaysLine(*peer, "refused"));
    EXPECT_EQ(peer->Wait(30s), 7);
  }
  srics::rl::WeightsUpdate got;
  srics::rl::LearnerReport got_stats;
  EXPECT_EQ(weights.Take(&got, 2s), TakeStatus::kTimeout);
  EXPECT_EQ(stats.Take(&got_stats, 100ms), TakeStatus::kTimeout);
  EXPECT_EQ(actor.counters(TopicId::kPolicyWeights).accepted + actor.counters(TopicId::kPolicyWeights).rejected, 0u);

  auto learner = Peer("learner", {"write-weights", "9"});
  EXPECT_TRUE(SaysLine(*learner, "published"));
  ASSERT_EQ(weights.Take(&got, 60s), TakeStatus::kSample);
  EXPECT_EQ(got.version, testing::MakePolicyWeights(9).version);
}

// A monitor process whose own enforcement is bypassed (here: a governance without write access
// control, signed with the CA key the test holds, so its writer is created and publishes)
// still delivers nothing to an actor of the run: the run's side refuses to match it.
TEST_F(SecurityTest, MonitorBypassingItsOwnChecksDeliversNothing) {
  const std::string lenient = CopyOfKeystore("-lenient");
  std::string governance;
  {
    std::stringstream text;
    text << std::ifstream(lenient + "/governance.xml").rdbuf();
    governance = text.str();
  }
  const std::string strict = "<enable_write_access_control>true";
  ASSERT_NE(governance.find(strict), std::string::npos);
  governance.replace(governance.find(strict), strict.size(), "<enable_write_access_control>false");
  std::ofstream(lenient + "/governance.xml") << governance;
  ASSERT_EQ(
      std::system(("openssl smime -sign -in " + lenient + "/governance.xml -text -out " + lenient +
                   "/governance.p7s -signer " + lenient + "/ca.cert.pem -inkey " + lenient + "/private/ca.key.pem")
                      .c_str()),
      0);

  Participant actor(Secured("actor-0"));
  Reader<srics::rl::WeightsUpdate> weights(actor);
  const config::TransportConfig c = Secured("monitor");
  PeerProcess monitor(SRICS_SECURITY_PEER,
                      {std::to_string(c.domain_id), c.run_id, lenient, "monitor", "write-weights", "12"});
  EXPECT_TRUE(SaysLine(monitor, "published"));  // its own check let it through
  srics::rl::WeightsUpdate got;
  EXPECT_EQ(weights.Take(&got, 5s), TakeStatus::kTimeout);
  EXPECT_EQ(actor.counters(TopicId::kPolicyWeights).accepted + actor.counters(TopicId::kPolicyWeights).rejected, 0u);
  fs::remove_all(lenient);
}

// A capture of the loopback traffic while the learner sends weights to an actor process and
// the actor sends 20 episodes back holds none of their numbers with the keystore, and holds
// them without it (the same exchange, open: the capture does see payloads). Root only.
TEST_F(SecurityTest, LoopbackCaptureHoldsNoPlaintextWeightsOrEpisodes) {
  if (!LoopbackCapture::Start()) GTEST_SKIP() << "capturing on lo needs CAP_NET_RAW (root)";
  // numbers no other test sends (their seeds come from this process's id)
  const uint64_t weights_seed = 7'000'000'000ull + static_cast<uint64_t>(getpid());
  const uint64_t episode_seed = 5'000'000'000ull + 100ull * static_cast<uint64_t>(getpid());
  const std::string weights_bytes = BytesOf(testing::MakePolicyWeights(weights_seed).parameters, 100, 16);
  std::vector<std::string> episode_bytes;
  for (uint64_t i = 0; i < 20; ++i)
    episode_bytes.push_back(BytesOf(testing::MakeEpisode(episode_seed + i).actions, 0, 16));
  for (const bool secured : {true, false}) {
    SCOPED_TRACE(secured ? "with the keystore" : "open");
    auto capture = LoopbackCapture::Start();
    ASSERT_TRUE(capture);
    config::TransportConfig c = Secured("learner");
    if (!secured) c.security = {};
    {
      Participant learner(c);
      Writer<rl::WeightsUpdate> weights(learner);
      Reader<rl::Episode> episodes(learner, testing::SampleEpisodeReader());
      const rl::WeightsUpdate published = testing::MakePolicyWeights(weights_seed);
      ASSERT_EQ(weights.Write(published), WriteResult::kSent);
      auto actor = Peer(secured ? "actor-0" : "", {"actor", "20", "60", std::to_string(episode_seed)});
      EXPECT_TRUE(SaysLine(*actor, "weights " + std::to_string(published.version)));
      EXPECT_TRUE(SaysLine(*actor, "wrote 20"));
      EXPECT_EQ(TakeEpisodes(episodes, 20, 30s), 20u);
      EXPECT_EQ(actor->Wait(30s), 0);
    }
    std::this_thread::sleep_for(200ms);  // the last frames reach the capture
    size_t seen = 0;
    for (const std::string& bytes : episode_bytes) seen += capture->Saw(bytes);
    if (secured) {
      EXPECT_FALSE(capture->Saw(weights_bytes)) << "plaintext weights on the wire";
      EXPECT_EQ(seen, 0u) << "plaintext episodes on the wire";
    } else {
      EXPECT_GT(seen, 0u) << "the capture saw no episode of the open exchange";
      if (!capture->Saw(weights_bytes)) std::cout << "(the capture missed the open weights sample)\n";
    }
  }
}

// Issue 39: with DDS Security an actor identity could publish episodes, evaluations and status
// under another actor's id. Each identity now writes the samples that name their sender in a
// partition of its own, the only one its signed permissions allow, and readers refuse a sample
// whose sender is not the identity of its partition. actor-1's episodes, evaluation and status
// that say actor 0 reach the learner's readers and are refused (episode.sender, eval.sender,
// status.sender), nothing of them is taken; a writer of actor-1 in actor-0's partition is
// refused by DDS Security; actor-1's own episodes (the control) are taken.
TEST_F(SecurityTest, AnActorIdentityCannotSpeakForAnotherActor) {
  Participant learner(Secured("learner"));
  Reader<rl::Episode> episodes(learner, testing::SampleEpisodeReader());
  Reader<rl::EvalReport> evals(learner);
  Reader<rl::NodeStatus> statuses(learner);

  auto forger = Peer("actor-1", {"actor-as", "0", "5", "60"});
  EXPECT_TRUE(SaysLine(*forger, "matched"));
  EXPECT_TRUE(SaysLine(*forger, "wrote 5"));
  EXPECT_EQ(forger->Wait(30s), 0);
  EXPECT_EQ(TakeEpisodes(episodes, 1, 3s), 0u);
  rl::EvalReport eval;
  EXPECT_EQ(evals.Take(&eval, 1s), TakeStatus::kTimeout);
  rl::NodeStatus status;
  EXPECT_EQ(statuses.Take(&status, 1s), TakeStatus::kTimeout);
  const auto rejections = learner.rejections();
  auto count = [&](const std::string& counter) {
    const auto it = rejections.find(counter);
    return it == rejections.end() ? uint64_t{0} : it->second;
  };
  EXPECT_EQ(count("episode.sender"), 5u) << RejectionSummary(rejections);
  EXPECT_EQ(count("eval.sender"), 1u) << RejectionSummary(rejections);
  EXPECT_EQ(count("status.sender"), 1u) << RejectionSummary(rejections);
  EXPECT_EQ(learner.counters(TopicId::kEpisode).accepted, 0u);

  auto intruder = Peer("actor-1", {"write-in-partition", "actor-0"});
  EXPECT_TRUE(SaysLine(*intruder, "refused"));
  EXPECT_EQ(intruder->Wait(30s), 7);

  auto honest = Peer("actor-1", {"actor", "3", "10"});  // no weights: 10 s of waiting for them
  EXPECT_TRUE(SaysLine(*honest, "wrote 3"));
  EXPECT_EQ(TakeEpisodes(episodes, 3, 30s), 3u);
  EXPECT_EQ(honest->Wait(30s), 0);
  EXPECT_EQ(learner.counters(TopicId::kEpisode).accepted, 3u);
}

// A whole secured run of the real role programs (a run of a few seconds): before issue 39's
// sender partitions, the launcher's own NodeStatus writer (one run id, one run) was refused by
// the keystore's permissions and a secured `srics run` could not start. Every role is heard,
// evaluations reach eval.csv, and nothing is refused.
TEST_F(SecurityTest, ASecuredRunFinishesWithEveryRoleHeard) {
  const config::TransportConfig c = Secured("launcher");
  const std::string run_dir = *keystore_ + ".secured-run", out = *keystore_ + ".secured-run.out";
  fs::remove_all(run_dir);
  std::string command = std::string(SRICS_LAUNCHER_BIN) + " run " + SRICS_SOURCE_DIR +
                        "/deploy/configs/rearrange-1-cpu.yaml --display plain --stop-timeout 10 --run-dir " + run_dir;
  for (const std::string set :
       {"run.total_env_steps=1500", "learner.warmup_steps=200", "agent.sac.batch_size=32",
        "learner.publish_every_updates=20", "learner.checkpoint_every_updates=100", "actors.count=2",
        "actors.eval_every_env_steps=500", "actors.eval_episodes=2", "graph.episodes=20", "graph.batch_windows=10",
        "graph.warmup_updates=10", "graph.kl_ramp_updates=10", "graph.min_updates=40", "graph.max_updates=40",
        "graph.eval_every_updates=20", "run.max_wall_minutes=0"})
    command += " --set " + set;
  command += " --set transport.domain_id=" + std::to_string(c.domain_id) + " --set transport.run_id=" + c.run_id +
             " --set transport.security.keystore=" + *keystore_ + " > " + out + " 2>&1";
  const int run_status = std::system(command.c_str());
  std::stringstream text;
  text << std::ifstream(out).rdbuf();
  ASSERT_TRUE(WIFEXITED(run_status)) << text.str();
  EXPECT_EQ(WEXITSTATUS(run_status), 0) << text.str();
  const auto read = ReadText;
  const std::string nodes = read(run_dir + "/nodes.csv"), evals = read(run_dir + "/eval.csv");
  for (const std::string node : {",learner,0,", ",graph,0,", ",actor,0,", ",actor,1,"})
    EXPECT_NE(nodes.find(node), std::string::npos) << node << " not in nodes.csv:\n" << nodes.substr(0, 2000);
  // the header, the passive baseline and evaluations of trained policies
  EXPECT_GE(std::count(evals.begin(), evals.end(), '\n'), 3) << evals;
  EXPECT_EQ(nodes.find(".sender="), std::string::npos) << nodes.substr(0, 4000);
  fs::remove_all(run_dir);
  fs::remove(out);
}

// make-keystore.sh on a keystore of the format before sender partitions (its permissions have
// no partitions and no format mark) re-makes the permissions, keeps key and certificate, and
// refuses role identities not named as their samples say.
TEST_F(SecurityTest, TheKeystoreScriptUpdatesOldPermissionsAndRefusesMisnamedRoles) {
  const std::string copy = CopyOfKeystore("-old");
  const auto read = ReadText;
  const std::string permissions = copy + "/identities/actor-1/permissions.xml";
  std::string old = read(permissions);
  const std::string mark = "; srics-permissions-format 2";
  ASSERT_NE(old.find(mark), std::string::npos);
  old.erase(old.find(mark), mark.size());
  std::ofstream(permissions) << old;
  const std::string cert = read(copy + "/identities/actor-1/cert.pem");
  const std::string script = std::string(SRICS_SOURCE_DIR) + "/deploy/security/make-keystore.sh " + copy;
  ASSERT_EQ(std::system((script + " > " + copy + ".log 2>&1").c_str()), 0) << read(copy + ".log");
  EXPECT_NE(read(copy + ".log").find("identity actor-1: permissions of an older format, made again"), std::string::npos)
      << read(copy + ".log");
  EXPECT_NE(read(permissions).find(mark), std::string::npos);
  EXPECT_NE(read(permissions).find("<partition>actor-1</partition>"), std::string::npos);
  EXPECT_EQ(read(copy + "/identities/actor-1/cert.pem"), cert);
  for (const std::string bad : {"actor-x=actor", "learner-2=learner", "launcher-b=launcher"}) {
    EXPECT_EQ(ExitCodeOf(script + " --add " + bad + " > " + copy + ".log 2>&1"), 2) << bad;
    EXPECT_FALSE(fs::exists(copy + "/identities/" + bad.substr(0, bad.find('=')))) << bad;
  }
  fs::remove_all(copy);
  fs::remove(copy + ".log");
}

// Revocation (issue 39): make-keystore.sh --revoke actor-1 puts actor-1's certificate on the
// CA's revocation list (crl.pem, which every participant loads) and gives actor-1 a new key.
// A learner with that list does not match a process still holding the old actor-1 identity
// (it sees "no reader" and the learner nothing, not even a sample to refuse); the re-keyed
// actor-1 is taken as before.
TEST_F(SecurityTest, ARevokedIdentityIsRefusedAndItsNewKeyWorks) {
  const std::string revoked = CopyOfKeystore("-revoked");
  const std::string script = std::string(SRICS_SOURCE_DIR) + "/deploy/security/make-keystore.sh " + revoked +
                             " --revoke actor-1 > " + revoked + ".log 2>&1";
  ASSERT_EQ(std::system(script.c_str()), 0);
  config::TransportConfig c = Secured("learner");
  c.security.keystore = revoked;
  Participant learner(c);
  Reader<rl::Episode> episodes(learner, testing::SampleEpisodeReader());

  // the old actor-1: the keystore it was given before the revocation
  auto old_key = Peer("actor-1", {"actor", "4", "8"});
  EXPECT_TRUE(SaysLine(*old_key, "no reader"));
  EXPECT_EQ(old_key->Wait(30s), 0);
  EXPECT_EQ(TakeEpisodes(episodes, 1, 2s), 0u);
  const SampleCounters counters = learner.counters(TopicId::kEpisode);
  EXPECT_EQ(counters.accepted + counters.rejected + counters.other_run, 0u);

  // the new actor-1
  PeerProcess new_key(SRICS_SECURITY_PEER,
                      {std::to_string(c.domain_id), c.run_id, revoked, "actor-1", "actor", "3", "8"});
  EXPECT_TRUE(SaysLine(new_key, "matched"));
  EXPECT_EQ(TakeEpisodes(episodes, 3, 30s), 3u);
  EXPECT_EQ(new_key.Wait(30s), 0);
  fs::remove_all(revoked);
  fs::remove(revoked + ".log");
}

// An identity's certificate with another identity's permissions (subject mismatch) and a
// permissions document not signed by the keystore's CA: the participant is refused.
TEST_F(SecurityTest, ForeignOrMismatchedPermissionsAreRefused) {
  const std::string copy = CopyOfKeystore("-tampered");
  fs::copy_file(copy + "/identities/learner/permissions.p7s", copy + "/identities/actor-0/permissions.p7s",
                fs::copy_options::overwrite_existing);
  // a second keystore's CA signs "learner" permissions for the monitor's subject name
  const std::string other = *keystore_ + "-other";
  fs::remove_all(other);
  ASSERT_EQ(std::system((std::string(SRICS_SOURCE_DIR) + "/deploy/security/make-keystore.sh " + other +
                         " --actors 0 > /dev/null 2>&1")
                            .c_str()),
            0);
  fs::copy_file(other + "/identities/monitor/permissions.p7s", copy + "/identities/monitor/permissions.p7s",
                fs::copy_options::overwrite_existing);
  for (const std::string identity : {"actor-0", "monitor"}) {
    config::TransportConfig c = Secured(identity);
    c.security.keystore = copy;
    try {
      Participant p(c);
      ADD_FAILURE() << identity << ": a participant was created";
    } catch (const DdsError& e) {
      EXPECT_NE(std::string(e.what()).find("with identity '" + identity + "' of keystore " + copy), std::string::npos)
          << e.what();
    }
  }
  fs::remove_all(copy);
  fs::remove_all(other);
}

// transport.security in the config: the keys, the domain range, and the check of the files
// before anything starts (the error names the missing file; role programs exit with 2).
TEST_F(SecurityTest, KeystoreConfigIsCheckedBeforeAnythingStarts) {
  const config::Config c = config::ParseConfig("transport:\n  security:\n    keystore: " + *keystore_ + "\n", "t.yaml");
  EXPECT_EQ(c.transport.security.keystore, *keystore_);
  EXPECT_EQ(config::CheckKeystore(c.transport.security, "actor-1"), "actor-1");
  auto error_of = [](auto f) {
    try {
      f();
    } catch (const config::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of([&] {
              config::CheckKeystore(c.transport.security, "actor-7");
            }).find(*keystore_ + "/identities/actor-7/cert.pem is missing"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              config::CheckKeystore({*keystore_ + "-nowhere", ""}, "learner");
            }).find("is not a folder"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              config::ParseConfig("transport:\n  domain_id: 231\n  security:\n    keystore: x\n", "t.yaml");
            }).find("0..230"),
            std::string::npos);
  EXPECT_NE(error_of([&] { config::ParseConfig("transport:\n  security:\n    keystor: x\n", "t.yaml"); }), "no error");

  // a role program whose identity is missing: exit 2 before DDS, naming the file
  const std::string out = *keystore_ + ".actor-out";
  const std::string command = std::string(SRICS_ACTOR_BIN) + " " + SRICS_SOURCE_DIR +
                              "/deploy/configs/default.yaml --id 7 --set transport.run_id=x --set "
                              "transport.security.keystore=" +
                              *keystore_ + " > " + out + " 2>&1";
  EXPECT_EQ(ExitCodeOf(command), 2);
  const std::string said = ReadText(out);
  EXPECT_NE(said.find("identities/actor-7/cert.pem is missing"), std::string::npos) << said;

  // srics run checks every process's identity before it starts any: three actors, two identities
  const std::string run_dir = *keystore_ + ".run";
  const std::string run = std::string(SRICS_LAUNCHER_BIN) + " run " + SRICS_SOURCE_DIR +
                          "/deploy/configs/default.yaml --actors 3 --display none --run-dir " + run_dir +
                          " --set transport.security.keystore=" + *keystore_ + " > " + out + " 2>&1";
  EXPECT_EQ(ExitCodeOf(run), 2);
  const std::string run_said = ReadText(out);
  EXPECT_NE(run_said.find("identities/actor-2/cert.pem is missing"), std::string::npos) << run_said;
  EXPECT_FALSE(fs::exists(run_dir + "/logs/learner.log")) << "a process was started";
  fs::remove_all(run_dir);
  fs::remove(out);
}

}  // namespace
}  // namespace srics::transport
