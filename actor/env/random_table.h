#pragma once
// Random rearrange tables with a known interaction graph, for checking that the graph service
// finds the graph of any table (not only the presets its settings were chosen on). A table
// draws the number of objects, each object's shape, size, mass and whether it is static, and
// which pairs of movable objects are tied by a rope or a spring. The graph it implies by
// construction is rl::GroundTruthGraph of the result (action -> arm, arm -> every movable
// object, both directions of every tie, nothing into a static object).

#include <cstdint>
#include <string>

#include "common/config/env_config.h"

namespace srics::env {

// Ranges of the draw (uniform unless said otherwise).
struct RandomTableOptions {
  int min_objects = 2;
  int max_objects = 5;
  double box_probability = 0.5;               // otherwise a cylinder
  double min_size = 0.025, max_size = 0.045;  // radius or half side (m)
  double min_mass = 0.05, max_mass = 0.3;     // kg
  // each object is static with this probability; at least two objects stay movable
  double static_probability = 0.25;
  // number of ties: 0, 1 or 2 with these probabilities (capped by the movable pairs)
  double one_tie_probability = 0.45, two_ties_probability = 0.2;
  double spring_probability = 0.5;                      // otherwise a rope
  double min_tie_length = 0.10, max_tie_length = 0.15;  // rope length or spring rest length
  double min_stiffness = 10, max_stiffness = 30;        // N/m
  int max_attempts = 1000;                              // draws until one passes config::CheckEnvConfig
};

// The table of `seed` (the same seed gives the same table on every machine). Every other
// field keeps its config::EnvConfig default. Throws std::runtime_error when no draw passes
// config::CheckEnvConfig within max_attempts.
config::EnvConfig RandomTable(uint64_t seed, const RandomTableOptions& options = {});

// The table as an environment preset file (YAML, `env:` section with its objects and
// connections), headed by comment lines that name the seed and `graph` (the graph by
// construction, rl::DescribeGraph(rl::GroundTruthGraph(table))).
std::string RandomTableYaml(const config::EnvConfig& table, uint64_t seed, const std::string& graph);

}  // namespace srics::env
