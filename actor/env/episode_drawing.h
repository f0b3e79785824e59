#pragma once
// An episode drawn from above: table and walls, objects (final pose, with their shape, size
// and colour), the hand, goals (rings in the object's colour, a cross for the hand),
// connections and every entity's trajectory. Written as PNG (libpng) or SVG. No MuJoCo.

#include <string>
#include <vector>

#include "actor/env/types.h"
#include "common/config/env_config.h"

namespace srics::env {

// Everything the drawing needs, independent of the simulator.
struct EpisodeTrace {
  config::EnvConfig config;                  // table, walls, hand and object catalogue
  std::vector<int> present;                  // catalogue entity numbers of entities 1..N-1
  std::vector<Vec2> goals;                   // per entity, arm first
  std::vector<std::vector<Vec2>> positions;  // per time step, per entity (arm first)
  std::string title;                         // drawn at the top (may be empty)
};

// Writes the picture; the format follows the file's extension (".png" or ".svg"). Throws
// std::runtime_error when the file cannot be written or the trace is inconsistent.
void DrawEpisode(const EpisodeTrace& trace, const std::string& path);

}  // namespace srics::env
