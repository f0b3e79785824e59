#include "common/config/sections.h"

namespace srics::config {

void ParseEnv(YamlSection s, EnvConfig* out) {
  s.ReadInt("num_pucks", &out->num_pucks, 1, 6);
  s.Finish();
}

}  // namespace srics::config
