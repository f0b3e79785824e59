#include <unistd.h>

#include <filesystem>

#include "common/config/sections.h"

namespace srics::config {

void ParseTransport(YamlSection s, TransportConfig* out) {
  // DDS domain ids are 0..232 (the RTPS port formula overflows above)
  s.ReadInt("domain_id", &out->domain_id, 0, 232);
  s.ReadString("run_id", &out->run_id, false);
  if (out->run_id.size() > 64) s.Fail("run_id", "at most 64 characters");
  s.ReadEnum("profile", &out->profile,
             {{"loopback", CycloneProfile::kLoopback},
              {"lan", CycloneProfile::kLan},
              {"unicast", CycloneProfile::kUnicast},
              {"file", CycloneProfile::kFile},
              {"environment", CycloneProfile::kEnvironment}});
  s.ReadString("cyclone_xml", &out->cyclone_xml);
  s.ReadString("network_interface", &out->network_interface);
  s.ReadString("peers", &out->peers);
  s.ReadInt("max_participants_per_host", &out->max_participants_per_host, 1, 1000);
  s.ReadInt("episode_history_depth", &out->episode_history_depth, 1, 1 << 20);
  s.ReadInt("writer_max_blocking_ms", &out->writer_max_blocking_ms, 1, 600000);
  s.ReadInt("episode_batch_ms", &out->episode_batch_ms, 0, 10000);
  s.ReadDouble("liveliness_lease_s", &out->liveliness_lease_s, 0.05, 3600);
  s.ReadDouble("status_period_s", &out->status_period_s, 0.01, 3600);
  s.ReadDouble("stalled_node_restart_s", &out->stalled_node_restart_s, 0, 86400);
  s.ReadInt("rejected_log_interval_s", &out->rejected_log_interval_s, 0, 3600);
  s.ReadInt("monitor_max_nodes", &out->monitor_max_nodes, 1, 1 << 20);
  s.ReadInt("monitor_max_runs", &out->monitor_max_runs, 1, 1 << 16);
  YamlSection security = s.Child("security");
  security.ReadString("keystore", &out->security.keystore);
  security.ReadString("identity", &out->security.identity);
  if (out->security.identity.find_first_of("/\\") != std::string::npos || out->security.identity == "." ||
      out->security.identity == "..")
    security.Fail("identity", "the name of a folder under the keystore's identities/ (e.g. monitor)");
  security.Finish();
  if (!out->security.keystore.empty() && out->domain_id > 230)
    s.FailRule("domain_id",
               "with transport.security.keystore, domain_id must be 0..230 (the range Cyclone 0.10's "
               "DDS Security governance parser accepts)");
  if (out->profile == CycloneProfile::kFile && out->cyclone_xml.empty())
    s.FailRule("cyclone_xml", "profile 'file' needs cyclone_xml: the path of a Cyclone XML file");
  if (out->profile == CycloneProfile::kUnicast && out->peers.empty())
    s.FailRule("peers", "profile 'unicast' needs peers: a comma-separated list of addresses");
  s.Finish();
}

KeystoreFiles KeystoreFilesOf(const SecurityConfig& security, const std::string& identity) {
  const std::filesystem::path dir = std::filesystem::absolute(security.keystore);
  const std::filesystem::path id = dir / "identities" / identity;
  return {(dir / "ca.cert.pem").string(), (dir / "governance.p7s").string(), (id / "cert.pem").string(),
          (id / "key.pem").string(),      (id / "permissions.p7s").string(), (dir / "crl.pem").string()};
}

std::string CheckKeystore(const SecurityConfig& security, const std::string& own_name) {
  if (security.keystore.empty()) return "";
  const std::string identity = security.identity.empty() ? own_name : security.identity;
  const std::string make = " (make the keystore with deploy/security/make-keystore.sh " + security.keystore +
                           ", which adds missing identities: --actors N, --add NAME=ROLE)";
  if (!std::filesystem::is_directory(security.keystore))
    throw ConfigError("transport.security.keystore: '" + security.keystore + "' is not a folder" + make);
  if (identity.empty())
    throw ConfigError("transport.security.identity: this process has no name of its own; set the identity");
  const KeystoreFiles files = KeystoreFilesOf(security, identity);
  for (const std::string& file :
       {files.ca_cert, files.governance, files.identity_cert, files.identity_key, files.permissions}) {
    if (!std::filesystem::is_regular_file(file))
      throw ConfigError("transport.security.keystore: " + file + " is missing (identity '" + identity + "')" + make);
    if (access(file.c_str(), R_OK) != 0)
      throw ConfigError("transport.security.keystore: " + file + " is not readable by this user");
  }
  return identity;
}

}  // namespace srics::config
