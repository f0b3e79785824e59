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
  s.ReadDouble("liveliness_lease_s", &out->liveliness_lease_s, 0.05, 3600);
  s.ReadDouble("status_period_s", &out->status_period_s, 0.01, 3600);
  s.ReadInt("rejected_log_interval_s", &out->rejected_log_interval_s, 0, 3600);
  if (out->profile == CycloneProfile::kFile && out->cyclone_xml.empty())
    s.FailRule("cyclone_xml", "profile 'file' needs cyclone_xml: the path of a Cyclone XML file");
  if (out->profile == CycloneProfile::kUnicast && out->peers.empty())
    s.FailRule("peers", "profile 'unicast' needs peers: a comma-separated list of addresses");
  s.Finish();
}

}  // namespace srics::config
