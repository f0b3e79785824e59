#pragma once
// DDS settings: which domain, which Cyclone configuration, and the knobs of the QoS table.

#include <string>

namespace srics::config {

enum class CycloneProfile {
  kLoopback,  // one host, many processes (deploy/cyclonedds/loopback.xml)
  kLan,       // one LAN with multicast (deploy/cyclonedds/lan.xml)
  kUnicast,   // several hosts listed as peers (deploy/cyclonedds/unicast.xml)
  kFile,      // the XML file given in cyclone_xml
  kEnvironment,  // whatever CYCLONEDDS_URI says (Cyclone's own default if unset)
};

// transport.run_id's default: `srics run` (and `srics sweep`) choose a run id unique to the
// launch (host, pid, time), recorded in the run folder's config.yaml so that a resumed run
// keeps it. Role programs started by hand refuse it: their run id must be the same on every
// host, so it is set explicitly.
inline constexpr const char* kAutoRunId = "auto";

struct TransportConfig {
  int domain_id = 42;
  std::string run_id = kAutoRunId;  // every topic carries it; two runs may share a domain
  CycloneProfile profile = CycloneProfile::kLoopback;
  std::string cyclone_xml;          // for profile: file
  std::string network_interface;    // for lan/unicast, e.g. "eth0" (empty: Cyclone chooses)
  std::string peers;                // for unicast: comma-separated addresses
  int max_participants_per_host = 64;  // Discovery/MaxAutoParticipantIndex on loopback
  int episode_history_depth = 256;  // reader-side keep-last depth for Episode (reliable)
  int writer_max_blocking_ms = 100;  // after this a full writer reports back-pressure
  double liveliness_lease_s = 2.0;   // NodeStatus writers: a dead peer is noticed after this
  double status_period_s = 1.0;      // NodeStatus and LearnerStats publishing period
  int rejected_log_interval_s = 5;   // rate limit for "dropped a malformed sample" warnings
};

}  // namespace srics::config
