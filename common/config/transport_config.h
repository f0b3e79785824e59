#pragma once
// DDS settings: which domain, which Cyclone configuration, and the knobs of the QoS table.

#include <string>

namespace srics::config {

enum class CycloneProfile {
  kLoopback,     // one host, many processes (deploy/cyclonedds/loopback.xml)
  kLan,          // one LAN with multicast (deploy/cyclonedds/lan.xml)
  kUnicast,      // several hosts listed as peers (deploy/cyclonedds/unicast.xml)
  kFile,         // the XML file given in cyclone_xml
  kEnvironment,  // whatever CYCLONEDDS_URI says (Cyclone's own default if unset)
};

// transport.run_id's default: `srics run` (and `srics sweep`) choose a run id unique to the
// launch (host, pid, time), recorded in the run folder's config.yaml so that a resumed run
// keeps it. Role programs started by hand refuse it: their run id must be the same on every
// host, so it is set explicitly.
inline constexpr const char* kAutoRunId = "auto";

// DDS Security (transport.security): a keystore made by deploy/security/make-keystore.sh.
// Empty keystore: security off (anyone on the domain may read and write every topic).
struct SecurityConfig {
  std::string keystore;  // the keystore folder (relative paths: to the working directory)
  std::string identity;  // identities/<identity>/ of the keystore; empty: the process's own
                         // name (learner, graph, actor-K, monitor, launcher), filled in at start
};

// The files a participant of `identity` loads from the keystore (absolute paths).
struct KeystoreFiles {
  std::string ca_cert;        // identity CA and permissions CA: ca.cert.pem
  std::string governance;     // governance.p7s
  std::string identity_cert;  // identities/<identity>/cert.pem
  std::string identity_key;   // identities/<identity>/key.pem
  std::string permissions;    // identities/<identity>/permissions.p7s
  std::string crl;            // crl.pem: the CA's revocation list (a keystore made before it has none)
};

struct TransportConfig {
  int domain_id = 42;
  std::string run_id = kAutoRunId;  // every topic carries it; two runs may share a domain
  CycloneProfile profile = CycloneProfile::kLoopback;
  std::string cyclone_xml;             // for profile: file
  std::string network_interface;       // for lan/unicast, e.g. "eth0" (empty: Cyclone chooses)
  std::string peers;                   // for unicast: comma-separated addresses
  int max_participants_per_host = 64;  // Discovery/MaxAutoParticipantIndex on loopback
  int episode_history_depth = 256;     // reader-side keep-last depth for Episode (reliable)
  int writer_max_blocking_ms = 100;    // after this a full writer reports back-pressure
  // Actors' episode writers pack episodes into shared datagrams and send each at most this
  // long after it was written (0: one datagram per episode, sent at once). Batching is what
  // lets one actor's writer reach ddsperf's rate (docs/results.md); the delay is a tenth of a
  // 20-step episode's time.
  int episode_batch_ms = 2;
  double liveliness_lease_s = 2.0;  // NodeStatus writers: a dead peer is noticed after this
  double status_period_s = 1.0;     // NodeStatus and LearnerStats publishing period
  // srics run kills (and so restarts) a role process whose NodeStatus stopped for this long
  // while the process still runs: hung, not dead (0 = never). Generous: a process starved of
  // CPU by other work also goes quiet, and a restart costs it its unsaved work
  double stalled_node_restart_s = 300;
  int rejected_log_interval_s = 5;  // rate limit for "dropped a malformed sample" warnings
  // What a monitor (the launcher's, srics-monitor, the dashboard) keeps of keys that come from
  // the wire: at most this many nodes (run, role, id) and runs; past it the one heard from
  // least goes first (counted, shown), so that a flood of invented ids keeps memory flat.
  int monitor_max_nodes = 1024;
  int monitor_max_runs = 64;
  SecurityConfig security;
};

// The keystore files of `identity` in `security.keystore` (no check that they exist).
KeystoreFiles KeystoreFilesOf(const SecurityConfig& security, const std::string& identity);

// With a keystore set: the identity the process uses (security.identity, or `own_name` when
// that is empty), after checking that every file it needs is there and readable; throws
// ConfigError "transport.security.keystore: <file> is missing ..." naming the file otherwise.
// Without a keystore: "" (nothing to check).
std::string CheckKeystore(const SecurityConfig& security, const std::string& own_name);

}  // namespace srics::config
