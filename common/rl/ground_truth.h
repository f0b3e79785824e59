#pragma once
// The interaction graph an environment config implies by construction: the action drives
// the arm, the arm can push every object that is not static, tied objects act on each other.
// Objects outside every object set (training and evaluation) take part in no edge.
// The graph service must find this graph; the in-process trainer may use it directly.

#include "common/config/env_config.h"
#include "common/rl/graph.h"

namespace srics::rl {

InteractionGraph GroundTruthGraph(const config::EnvConfig& env);

}  // namespace srics::rl
