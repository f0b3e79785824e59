#pragma once
// Hand-built samples for the monitor tests.

#include "common/transport/wire.h"

namespace srics::monitor::testing {

inline rl::NodeStatus Node(const std::string& role, uint32_t id, rl::NodePhase phase) {
  rl::NodeStatus s;
  s.role = role;
  s.node_id = id;
  s.host = "host-" + role;
  s.pid = 1000 + static_cast<int>(id);
  s.uptime_ms = 61000;
  s.report.phase = phase;
  s.report.policy_version = 7;
  s.report.graph_version = 1;
  s.report.steps = 12345;
  return s;
}

// An evaluation as received (floats at the wire's precision).
inline rl::EvalReport Eval(uint64_t policy_version, uint64_t env_steps, float object_distance) {
  rl::EvalReport e;
  e.actor_id = 0;
  e.policy_version = policy_version;
  e.graph_version = 1;
  e.env_steps = env_steps;
  rl::EvaluationSummary& s = e.summary;
  s.episodes = 20;
  s.avg_distance = object_distance + 0.01f;
  s.avg_object_distance = object_distance;
  s.success_rate = 0.5f;
  s.entity_distance = {0.01f, 0.1f, 0.2f};
  s.subgoal_success = {1.0f, 0.8f, 0.25f};
  s.selectivity = 0.75f;
  s.selectivity_episodes = s.episodes;
  return e;
}

// A graph as received (floats at the wire's precision, the structure as sent).
inline rl::GraphUpdate Graph() {
  rl::GraphUpdate g;
  g.version = 3;
  g.graph.num_entities = 3;
  // 0 -> 1, 1 -> 2 (and a self weight that must not count as an edge)
  g.mean_weights = {0.9f, 0.93f, 0.1f, 0.0f, 0.8f, 0.71f, 0.0f, 0.05f, 0.6f};
  g.graph.adjacency = {1, 1, 0, 0, 1, 1, 0, 0, 1};
  g.graph.action_entity = 0;
  g.threshold = 0.5f;
  g.structure.ancestor_mask = {1, 3, 7};
  g.structure.depth = {0, 1, -1};
  g.held_out_loss = 0.0123f;
  g.episodes_used = 400;
  return g;
}

// The learner's count against the budget: training_env_steps where the contract has it (a
// template, so the tests build against either version of the learner stats).
template <typename Stats>
void SetTrainingSteps(Stats* stats, uint64_t steps) {
  if constexpr (requires { stats->training_env_steps; }) {
    stats->training_env_steps = steps;
    stats->transitions_inserted = steps + 2000;  // exploration counts here, not in the budget
  } else {
    stats->transitions_inserted = steps;
  }
}

}  // namespace srics::monitor::testing
