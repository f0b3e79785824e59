#include "common/rl/agent_shape.h"

#include <algorithm>

#include "common/nn/serialize.h"

namespace srics::rl {

AgentShape AgentShapeFor(const config::EnvConfig& env, config::Method method, config::ObjectTies ties) {
  const int objects = static_cast<int>(config::EffectiveObjects(env).size());
  const int kinds = 1 + objects;
  AgentShape shape;
  shape.entity_dim = kinds + (env.velocities ? 4 : 2);
  const bool full_goal = method == config::Method::kSacHer || method == config::Method::kHac;
  shape.goal_dim = full_goal ? 2 * (1 + objects) : kinds + 3;
  shape.action_dim = 2;
  shape.goal_tokens = ties == config::ObjectTies::kJoint && UsesGraph(method) ? 2 : 1;
  return shape;
}

AgentShape HighLevelShapeFor(const config::EnvConfig& env) {
  AgentShape shape = AgentShapeFor(env, config::Method::kHac);
  shape.action_dim = shape.goal_dim;
  return shape;
}

config::AgentConfig HighLevelAgentConfig(const config::AgentConfig& agent, const AgentShape& low,
                                         const AgentShape& high) {
  config::AgentConfig c = agent;
  c.sac.target_entropy = agent.sac.target_entropy * high.action_dim / low.action_dim;
  return c;
}

EpisodeLimits EpisodeLimitsFor(const config::EnvConfig& env) {
  const int objects = static_cast<int>(config::EffectiveObjects(env).size());
  // entity counts of the sets episodes draw from (as SampleObjectSet): no sets = every object
  std::vector<int> counts;
  auto add = [&](const std::vector<std::vector<int>>& sets) {
    if (sets.empty()) counts.push_back(1 + objects);
    for (const auto& set : sets) counts.push_back(1 + static_cast<int>(set.size()));
  };
  add(env.object_sets);
  add(env.eval_object_sets.empty() ? env.object_sets : env.eval_object_sets);
  EpisodeLimits limits;
  limits.min_entities = *std::min_element(counts.begin(), counts.end());
  limits.max_entities = *std::max_element(counts.begin(), counts.end());
  limits.num_kinds = 1 + objects;
  limits.velocities = env.velocities;
  limits.action_dim = AgentShapeFor(env, config::Method::kSrics).action_dim;  // every method's
  return limits;
}

EnvironmentShape FullEnvironmentShapeFor(const config::EnvConfig& env) {
  const int objects = static_cast<int>(config::EffectiveObjects(env).size());
  EnvironmentShape shape;
  shape.layout = {1 + objects, 1 + objects, env.velocities};
  for (int kind = 0; kind <= objects; ++kind) shape.entity_kinds.push_back(static_cast<uint16_t>(kind));
  shape.action_dim = AgentShapeFor(env, config::Method::kSrics).action_dim;
  for (std::vector<int> set : env.object_sets) {
    std::sort(set.begin(), set.end());  // the order the environment presents them in
    std::vector<uint16_t> kinds = {0};
    for (int object : set) kinds.push_back(static_cast<uint16_t>(object));
    shape.episode_kinds.push_back(std::move(kinds));
  }
  return shape;
}

RunShape RunShapeFor(const config::Config& config) {
  RunShape shape;
  shape.agent = AgentShapeFor(config.env, config.run.method, config.graph.object_ties);
  shape.high = HighLevelShapeFor(config.env);
  shape.limits = EpisodeLimitsFor(config.env);
  shape.full = FullEnvironmentShapeFor(config.env);
  shape.subgoal_box = SubgoalBoxFor(config.env);
  return shape;
}

AttentionNetworkConfig MakeNetworkConfig(const AgentShape& shape, const config::AgentConfig& agent) {
  AttentionNetworkConfig c;
  c.entity_dim = shape.entity_dim;
  c.goal_dim = shape.goal_dim;
  c.goal_tokens = shape.goal_tokens;
  c.action_dim = shape.action_dim;
  c.embed_dim = agent.network.embed_dim;
  c.num_heads = agent.network.heads;
  c.policy_hidden = agent.network.policy_hidden;
  c.q_hidden = agent.network.q_hidden;
  c.log_std_min = agent.network.log_std_min;
  c.log_std_max = agent.network.log_std_max;
  c.initial_policy_std = agent.network.initial_policy_std;
  c.hidden_bias = agent.network.hidden_bias;
  c.Validate();
  return c;
}

std::string PolicySignature(PolicyNetwork<float>& policy) {
  // goal tokens change no parameter's shape, yet what the weights mean
  const int tokens = policy.config().goal_tokens;
  return "attention-policy/" + std::to_string(nn::SignatureHash(policy.Parameters())) +
         (tokens > 1 ? "/goal-tokens-" + std::to_string(tokens) : "");
}

std::string HacPolicySignature(PolicyNetwork<float>& high, PolicyNetwork<float>& low) {
  return "hac-policy/" + std::to_string(nn::SignatureHash(high.Parameters())) + "+" +
         std::to_string(nn::SignatureHash(low.Parameters()));
}

bool UsesGraph(config::Method method) {
  return method == config::Method::kSrics || method == config::Method::kSricsNoSelectivity ||
         method == config::Method::kSricsNoSelectivityNoOrder;
}

}  // namespace srics::rl
