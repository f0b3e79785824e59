#include "common/config/sections.h"

namespace srics::config {

void ParseRun(YamlSection s, RunConfig* out) {
  s.ReadString("name", &out->name, false);
  s.ReadUint64("seed", &out->seed);
  s.ReadEnum("method", &out->method,
             {{"srics", Method::kSrics},
              {"srics_no_selectivity", Method::kSricsNoSelectivity},
              {"srics_no_selectivity_no_order", Method::kSricsNoSelectivityNoOrder},
              {"smorl", Method::kSmorl},
              {"sac_her", Method::kSacHer},
              {"hac", Method::kHac}});
  s.ReadUint64("total_env_steps", &out->total_env_steps, 1);
  s.ReadDouble("max_wall_minutes", &out->max_wall_minutes, 0, 1e6);
  s.ReadString("output_dir", &out->output_dir, false);
  s.ReadEnum("log_level", &out->log_level,
             std::vector<std::pair<std::string, std::string>>{{"trace", "trace"},
                                                              {"debug", "debug"},
                                                              {"info", "info"},
                                                              {"warn", "warn"},
                                                              {"error", "error"},
                                                              {"off", "off"}});
  s.ReadBool("log_to_file", &out->log_to_file);
  // recorded in the resolved settings only when given: runs made before the key resume unchanged
  if (s.Has("in_process_threads")) s.ReadInt("in_process_threads", &out->in_process_threads, 1, 2);
  s.Finish();
}

}  // namespace srics::config
