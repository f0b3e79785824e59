#pragma once
// MJCF text of a rearrange environment, generated from its config (no MuJoCo call here).
//
// Bodies: "mocap" (mocap body), "hand" (free joint, welded to the mocap), "object<i>" for
// every catalogue object i = 1..n (free joint "object<i>", collision geom "object<i>", centre
// site "site<i>"). Connections become spatial tendons between the sites. Objects absent from
// an episode are parked off the table by the environment.

#include <string>

#include "actor/env/types.h"
#include "common/config/env_config.h"

namespace srics::env {

// The whole model as MJCF text.
std::string GenerateRearrangeMjcf(const config::EnvConfig& config);

// Where catalogue object `entity` (1..n) rests when absent: a row far off the table.
Vec2 ParkingPosition(const config::EnvConfig& config, int entity);

// Display colour of catalogue object `entity` (1..n): its rgb or the palette's.
std::array<double, 3> ObjectColor(const config::EnvConfig& config, int entity);

}  // namespace srics::env
