#pragma once
// The rearrange environment family (srics-method.md section 1). Defaults: Rearrange 3.
// Owned by actor/env; parsed in env_config.cc.

#include <vector>

namespace srics::config {

struct EnvConfig {
  int num_pucks = 3;
};

}  // namespace srics::config
