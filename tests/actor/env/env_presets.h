#pragma once
// The environment presets of deploy/configs/env/ as the environment tests load them.

#include <string>

#include "common/config/config.h"

namespace srics::env::testing {

// deploy/configs/env/<name>.yaml in the source tree.
inline std::string PresetPath(const std::string& name) {
  return std::string(SRICS_SOURCE_DIR) + "/deploy/configs/env/" + name + ".yaml";
}

// The env section of that preset, loaded and validated.
inline config::EnvConfig Preset(const std::string& name) { return config::LoadConfig(PresetPath(name)).env; }

}  // namespace srics::env::testing
