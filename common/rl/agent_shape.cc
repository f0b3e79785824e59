#include "common/rl/agent_shape.h"

#include "common/nn/serialize.h"

namespace srics::rl {

AgentShape AgentShapeFor(const config::EnvConfig& env, config::Method method) {
  const int objects = static_cast<int>(config::EffectiveObjects(env).size());
  const int kinds = 1 + objects;
  AgentShape shape;
  shape.entity_dim = kinds + (env.velocities ? 4 : 2);
  shape.goal_dim = method == config::Method::kSacHer ? 2 * (1 + objects) : kinds + 3;
  shape.action_dim = 2;
  return shape;
}

AttentionNetworkConfig MakeNetworkConfig(const AgentShape& shape, const config::AgentConfig& agent) {
  AttentionNetworkConfig c;
  c.entity_dim = shape.entity_dim;
  c.goal_dim = shape.goal_dim;
  c.action_dim = shape.action_dim;
  c.embed_dim = agent.network.embed_dim;
  c.num_heads = agent.network.heads;
  c.policy_hidden = agent.network.policy_hidden;
  c.q_hidden = agent.network.q_hidden;
  c.log_std_min = agent.network.log_std_min;
  c.log_std_max = agent.network.log_std_max;
  c.Validate();
  return c;
}

std::string PolicySignature(PolicyNetwork<float>& policy) {
  return "attention-policy/" + std::to_string(nn::SignatureHash(policy.Parameters()));
}

bool UsesGraph(config::Method method) {
  return method == config::Method::kSrics || method == config::Method::kSricsNoSelectivity ||
         method == config::Method::kSricsNoSelectivityNoOrder;
}

}  // namespace srics::rl
