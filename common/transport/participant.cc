#include "common/transport/participant.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "common/process/memory.h"
#include "common/transport/dds_util.h"

namespace srics::transport {

DdsError::DdsError(const std::string& operation, int32_t retcode)
    : std::runtime_error(operation + ": " + dds_strretcode(retcode) + " (" + std::to_string(retcode) + ")"),
      retcode_(retcode) {}

namespace internal {

// Samples per instance that readers of PolicyWeights and InteractionGraph keep (CreateQos).
constexpr int32_t kLatestReaderDepth = 8;

dds_qos_t* CreateQos(const TopicSpec& spec, Side side, const config::TransportConfig& config) {
  dds_qos_t* qos = dds_create_qos();
  // a blocked reliable write gives up after this and reports back-pressure
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(config.writer_max_blocking_ms));
  dds_qset_durability(
      qos, spec.durability == Durability::kTransientLocal ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  if (spec.history == HistoryKind::kKeepAllBounded) {
    dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
    // a reader that is full does not acknowledge: the writer blocks instead of data being lost
    if (side == Side::kReader)
      dds_qset_resource_limits(qos, config.episode_history_depth, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  } else {
    // Readers of the run's latest weights and graph keep a few samples of the one instance: a
    // late joiner gets the newest sample of every matched writer, and with one slot a
    // stranger's (refused afterwards) could displace the run's own, which is not sent again
    // (the graph service publishes only on a change).
    const bool latest = spec.id == TopicId::kPolicyWeights || spec.id == TopicId::kInteractionGraph;
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST,
                     side == Side::kReader && latest ? std::max(spec.depth, kLatestReaderDepth) : spec.depth);
  }
  if (spec.liveliness_lease && side == Side::kWriter)
    dds_qset_liveliness(qos, DDS_LIVELINESS_AUTOMATIC, static_cast<dds_duration_t>(config.liveliness_lease_s * 1e9));
  // Under DDS Security a sample that names its sender travels in the partition of the writer's
  // identity, which only that identity's permissions allow; readers take every partition and
  // check the sender against it (the Reader). Open, everything stays in the default partition,
  // where external monitors look.
  if (spec.names_sender && !config.security.keystore.empty())
    dds_qset_partition1(qos, side == Side::kWriter ? config.security.identity.c_str() : "*");
  return qos;
}

}  // namespace internal

std::string SenderIdentity(std::string_view role, uint32_t id) {
  if (role == "actor") return "actor-" + std::to_string(id);
  return std::string(role);
}

namespace {

// Domains this process created, shared by its participants: Cyclone allows one configuration
// per domain id and process, and deleting the domain entity deletes its participants.
struct DomainEntry {
  int32_t handle = 0;
  std::string xml;
  int users = 0;
};

std::mutex& DomainMutex() {
  static std::mutex mutex;
  return mutex;
}

std::map<int, DomainEntry>& Domains() {
  static auto* domains = new std::map<int, DomainEntry>();
  return *domains;
}

// Participant QoS with the DDS Security properties of the keystore identity (nullptr without a
// keystore): Cyclone's built-in plugins (Debian ships them in libddsc0debian/) and the files.
dds_qos_t* SecurityQos(const config::SecurityConfig& security) {
  const std::string identity = config::CheckKeystore(security, "");
  if (identity.empty()) return nullptr;
  const config::KeystoreFiles files = config::KeystoreFilesOf(security, identity);
  dds_qos_t* qos = dds_create_qos();
  const std::pair<const char*, std::string> properties[] = {
      {"dds.sec.auth.library.path", "dds_security_auth"},
      {"dds.sec.auth.library.init", "init_authentication"},
      {"dds.sec.auth.library.finalize", "finalize_authentication"},
      {"dds.sec.crypto.library.path", "dds_security_crypto"},
      {"dds.sec.crypto.library.init", "init_crypto"},
      {"dds.sec.crypto.library.finalize", "finalize_crypto"},
      {"dds.sec.access.library.path", "dds_security_ac"},
      {"dds.sec.access.library.init", "init_access_control"},
      {"dds.sec.access.library.finalize", "finalize_access_control"},
      {"dds.sec.auth.identity_ca", "file:" + files.ca_cert},
      {"dds.sec.auth.identity_certificate", "file:" + files.identity_cert},
      {"dds.sec.auth.private_key", "file:" + files.identity_key},
      {"dds.sec.access.permissions_ca", "file:" + files.ca_cert},
      {"dds.sec.access.governance", "file:" + files.governance},
      {"dds.sec.access.permissions", "file:" + files.permissions},
  };
  for (const auto& [name, value] : properties) dds_qset_prop(qos, name, value.c_str());
  // the CA's revocation list: Cyclone's auth plugin refuses a revoked certificate at the
  // handshake (make-keystore.sh --revoke)
  if (std::filesystem::is_regular_file(files.crl))
    dds_qset_prop(qos, "org.eclipse.cyclonedds.sec.auth.crl", ("file:" + files.crl).c_str());
  return qos;
}

}  // namespace

Participant::Participant(const config::TransportConfig& config, Shutdown& shutdown)
    : config_(config), shutdown_(&shutdown), counters_(std::make_shared<CounterTable>()) {
  // Cyclone's receive thread allocates each message's buffers and frees them once delivered:
  // with glibc's defaults every burst of episodes grew its arena again through page faults (8%
  // of the receive thread; kept arenas: bench_transport's actor path 0.87 of the wall time,
  // farm-bench, 8 pairs). The one heap policy of every process (process::SetUpHeap) keeps them.
  process::SetUpHeap();
  const std::string xml = CycloneConfigFor(config);
  if (!xml.empty()) {
    std::lock_guard<std::mutex> lock(DomainMutex());
    DomainEntry& entry = Domains()[config.domain_id];
    if (entry.users == 0) {
      entry.handle = internal::Check(dds_create_domain(config.domain_id, xml.c_str()),
                                     "dds_create_domain (check the Cyclone XML)");
      entry.xml = xml;
    } else if (entry.xml != xml) {
      throw std::invalid_argument("transport: domain " + std::to_string(config.domain_id) +
                                  " is already configured differently in this process");
    }
    ++entry.users;
    holds_domain_ = true;
  }
  try {
    dds_qos_t* qos = SecurityQos(config.security);
    const dds_entity_t participant = dds_create_participant(config.domain_id, qos, nullptr);
    if (qos) dds_delete_qos(qos);
    // Cyclone reports most refusals of the security plugins as a plain error: name the identity
    if (qos && participant < 0)
      throw DdsError("dds_create_participant with identity '" + config.security.identity + "' of keystore " +
                         config.security.keystore +
                         " (DDS Security refuses a certificate or permissions not signed by the keystore's CA, "
                         "expired, or of another subject; Cyclone's log says which)",
                     participant);
    participant_ = internal::Check(participant, "dds_create_participant");
    guard_ = internal::Check(dds_create_guardcondition(participant_), "dds_create_guardcondition");
    shutdown_->Register(guard_);
  } catch (...) {
    Release();
    throw;
  }
}

Participant::~Participant() { Release(); }

void Participant::Release() {
  if (guard_ > 0) shutdown_->Unregister(guard_);
  // deleting the participant deletes its topics, readers, writers, waitsets and guard
  internal::DeleteEntity(&participant_);
  guard_ = 0;
  if (holds_domain_) {
    std::lock_guard<std::mutex> lock(DomainMutex());
    auto it = Domains().find(config_.domain_id);
    if (it != Domains().end() && --it->second.users == 0) {
      dds_delete(it->second.handle);
      Domains().erase(it);
    }
    holds_domain_ = false;
  }
}

Participant::Participant(Participant&& other) noexcept
    : config_(std::move(other.config_)),
      shutdown_(other.shutdown_),
      participant_(std::exchange(other.participant_, 0)),
      guard_(std::exchange(other.guard_, 0)),
      holds_domain_(std::exchange(other.holds_domain_, false)),
      counters_(std::move(other.counters_)) {}

Participant& Participant::operator=(Participant&& other) noexcept {
  if (this != &other) {
    Release();
    config_ = std::move(other.config_);
    shutdown_ = other.shutdown_;
    participant_ = std::exchange(other.participant_, 0);
    guard_ = std::exchange(other.guard_, 0);
    holds_domain_ = std::exchange(other.holds_domain_, false);
    counters_ = std::move(other.counters_);
  }
  return *this;
}

SampleCounters Participant::counters(TopicId topic) const {
  const auto& row = counters_->rows[static_cast<size_t>(topic)];
  return {row.accepted.load(), row.rejected.load(), row.other_run.load()};
}

uint64_t Participant::total_rejected() const {
  uint64_t total = 0;
  for (const auto& [counter, count] : counters_->Rejections()) total += count;
  return total;
}

void CounterTable::CountRejection(std::string_view counter) {
  std::lock_guard lock(mutex_);
  if (auto it = rejections_.find(counter); it != rejections_.end())
    ++it->second;
  else
    rejections_.emplace(std::string(counter), 1);
}

std::map<std::string, uint64_t, std::less<>> CounterTable::Rejections() const {
  std::lock_guard lock(mutex_);
  return rejections_;
}

std::string RejectionSummary(const std::map<std::string, uint64_t, std::less<>>& rejections) {
  std::string text;
  for (const auto& [counter, count] : rejections) {
    if (count == 0) continue;
    if (!text.empty()) text += ' ';
    text += counter + "=" + std::to_string(count);
  }
  return text;
}

}  // namespace srics::transport
