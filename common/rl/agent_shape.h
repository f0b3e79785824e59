#pragma once
// The contract between actors and the learner about the networks: their sizes follow from
// the environment config and the method, and a policy is identified by its signature. Both
// sides call these, so a mismatch can only come from different configs (and is refused).

#include <string>

#include "common/config/agent_config.h"
#include "common/config/config.h"
#include "common/config/env_config.h"
#include "common/config/graph_config.h"
#include "common/config/run_config.h"
#include "common/rl/episode.h"
#include "common/rl/hac.h"
#include "common/rl/networks.h"

namespace srics::rl {

// Sizes the networks need from the environment and method.
struct AgentShape {
  int entity_dim = 0;
  int goal_dim = 0;  // one goal token's floats
  int action_dim = 2;
  int goal_tokens = 1;  // 2: a tied pair is attempted as one subgoal (graph.object_ties: joint)
};

// Entity tokens of K + 2 (+ 2 with velocities) floats for K = 1 + catalogue objects, goal
// tokens of K + 3 (subgoals) or 2N (SAC+HER's full goal, HAC's subgoal of every entity),
// actions of 2. For HAC this is the low level; N = 1 + catalogue objects. Two goal tokens for
// the methods that use a graph when `ties` is joint, one otherwise.
AgentShape AgentShapeFor(const config::EnvConfig& env, config::Method method,
                         config::ObjectTies ties = config::ObjectTies::kTwoWay);

// HAC's high level: the full goal (2N) as goal token, a subgoal (2N) as action.
AgentShape HighLevelShapeFor(const config::EnvConfig& env);
// HAC's high-level agent settings: the shared ones, with the entropy target per action
// dimension kept (sac.target_entropy is -|A| for the low level's actions).
config::AgentConfig HighLevelAgentConfig(const config::AgentConfig& agent, const AgentShape& low,
                                         const AgentShape& high);

// What this environment's episodes look like: the entity count ranges over the object sets
// (training and evaluation), the kinds, velocities and action size are the run's.
EpisodeLimits EpisodeLimitsFor(const config::EnvConfig& env);

// The environment with every object present: the arm (kind 0), then catalogue object i as
// kind i. The shape of the graph service's data set and of the run's graphs, from the config
// alone (never from what some peer published first).
struct EnvironmentShape {
  EntityLayout layout;
  std::vector<uint16_t> entity_kinds;
  int action_dim = 0;
  // With object_sets: the entity kinds of each training combination's episodes (the arm, then
  // the set's objects in increasing order, as the environment presents them). Empty: every
  // episode presents the whole catalogue (`entity_kinds`).
  std::vector<std::vector<uint16_t>> episode_kinds;
};
EnvironmentShape FullEnvironmentShapeFor(const config::EnvConfig& env);

// What every role of a run sizes itself by, derived from the config once where the roles are
// composed (RunInProcess, each role's main, srics eval) and handed to each role's *OptionsFor,
// so that no role derives it again.
struct RunShape {
  AgentShape agent;        // the run's method's networks (HAC: its low level)
  AgentShape high;         // HAC's high level (HighLevelShapeFor)
  EpisodeLimits limits;    // what an episode of this run may look like (EpisodeLimitsFor)
  EnvironmentShape full;   // every object present (FullEnvironmentShapeFor)
  SubgoalBox subgoal_box;  // HAC's subgoal region (SubgoalBoxFor)
  // the arm and every catalogue object (graphs are over these)
  int entities() const { return full.layout.num_entities; }
};
RunShape RunShapeFor(const config::Config& config);

// The network configuration for a shape and the agent config.
AttentionNetworkConfig MakeNetworkConfig(const AgentShape& shape, const config::AgentConfig& agent);

// The architecture signature PolicyWeights carries: actors refuse weights whose signature
// differs from their own network's.
std::string PolicySignature(PolicyNetwork<float>& policy);
// HAC's weights are the high level's parameters, then the low level's, with this signature.
std::string HacPolicySignature(PolicyNetwork<float>& high, PolicyNetwork<float>& low);

// True for the methods that use the learned interaction graph.
bool UsesGraph(config::Method method);

}  // namespace srics::rl
