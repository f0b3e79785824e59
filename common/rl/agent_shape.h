#pragma once
// The contract between actors and the learner about the networks: their sizes follow from
// the environment config and the method, and a policy is identified by its signature. Both
// sides call these, so a mismatch can only come from different configs (and is refused).

#include <string>

#include "common/config/agent_config.h"
#include "common/config/env_config.h"
#include "common/config/run_config.h"
#include "common/rl/episode.h"
#include "common/rl/networks.h"

namespace srics::rl {

// Sizes the networks need from the environment and method.
struct AgentShape {
  int entity_dim = 0;
  int goal_dim = 0;
  int action_dim = 2;
};

// Entity tokens of K + 2 (+ 2 with velocities) floats for K = 1 + catalogue objects, goal
// tokens of K + 3 (subgoals) or 2N (SAC+HER's full goal), actions of 2.
AgentShape AgentShapeFor(const config::EnvConfig& env, config::Method method);

// What this environment's episodes look like: the entity count ranges over the object sets
// (training and evaluation), the kinds, velocities and action size are the run's.
EpisodeLimits EpisodeLimitsFor(const config::EnvConfig& env);

// The network configuration for a shape and the agent config.
AttentionNetworkConfig MakeNetworkConfig(const AgentShape& shape, const config::AgentConfig& agent);

// The architecture signature PolicyWeights carries: actors refuse weights whose signature
// differs from their own network's.
std::string PolicySignature(PolicyNetwork<float>& policy);

// True for the methods that use the learned interaction graph.
bool UsesGraph(config::Method method);

}  // namespace srics::rl
