#include "common/transport/rl_convert.h"

#include <stdexcept>

namespace srics::transport {

Episode ToMessage(const rl::Episode& e) {
  Episode m;
  m.actor_id = e.actor_id;
  m.episode_id = e.episode_id;
  m.mode = e.mode == rl::EpisodeMode::kExplore ? EpisodeMode::kExplore
           : e.mode == rl::EpisodeMode::kTrain ? EpisodeMode::kTrain
                                               : EpisodeMode::kEval;
  m.policy_version = e.policy_version;
  m.graph_version = e.graph_version;
  m.num_entities = static_cast<uint16_t>(e.layout.num_entities);
  m.entity_dim = static_cast<uint16_t>(e.layout.entity_dim());
  m.action_dim = static_cast<uint16_t>(e.action_dim);
  m.num_steps = static_cast<uint16_t>(e.num_steps);
  m.entity_kinds = e.entity_kinds;
  m.states = e.states;
  m.actions = e.actions;
  m.subgoal_entity = static_cast<int16_t>(e.subgoal_entity);
  m.goal = e.goal;
  m.ancestor_mask = e.ancestor_mask;
  return m;
}

rl::Episode FromMessage(const Episode& m, bool velocities) {
  rl::Episode e;
  const int extra = velocities ? 4 : 2;
  if (m.entity_dim <= extra)
    throw std::invalid_argument("entity_dim " + std::to_string(m.entity_dim) + " leaves no room for identifiers");
  e.layout = {m.num_entities, m.entity_dim - extra, velocities};
  e.entity_kinds = m.entity_kinds;
  e.num_steps = m.num_steps;
  e.action_dim = m.action_dim;
  e.states = m.states;
  e.actions = m.actions;
  e.subgoal_entity = m.subgoal_entity;
  e.goal = m.goal;
  e.ancestor_mask = m.ancestor_mask;
  e.mode = m.mode == EpisodeMode::kExplore ? rl::EpisodeMode::kExplore
           : m.mode == EpisodeMode::kTrain ? rl::EpisodeMode::kTrain
                                           : rl::EpisodeMode::kEval;
  e.actor_id = m.actor_id;
  e.episode_id = m.episode_id;
  e.policy_version = m.policy_version;
  e.graph_version = m.graph_version;
  return e;
}

InteractionGraph ToMessage(const rl::InteractionGraph& graph, const rl::SubgoalStructure& structure,
                           const std::vector<double>& mean_weights, float threshold, uint64_t version,
                           float held_out_loss, uint64_t training_updates, uint32_t episodes_used) {
  InteractionGraph m;
  m.version = version;
  m.num_entities = static_cast<uint16_t>(graph.num_entities);
  m.mean_weights.assign(mean_weights.begin(), mean_weights.end());
  m.adjacency = graph.adjacency;
  m.action_entity = static_cast<int16_t>(graph.action_entity);
  m.threshold = threshold;
  m.ancestor_masks = structure.ancestor_mask;
  for (int d : structure.depth) m.depths.push_back(static_cast<int16_t>(d));
  m.held_out_loss = held_out_loss;
  m.training_updates = training_updates;
  m.episodes_used = episodes_used;
  return m;
}

ReceivedGraph FromMessage(const InteractionGraph& m) {
  ReceivedGraph r;
  r.version = m.version;
  r.graph.num_entities = m.num_entities;
  r.graph.adjacency = m.adjacency;
  r.graph.action_entity = m.action_entity;
  const std::string problem = rl::ValidateGraph(r.graph);
  if (!problem.empty()) throw std::invalid_argument("interaction graph: " + problem);
  r.structure = rl::ComputeSubgoalStructure(r.graph);
  if (m.ancestor_masks != r.structure.ancestor_mask)
    throw std::invalid_argument("interaction graph: ancestor sets disagree with the adjacency");
  for (size_t i = 0; i < m.depths.size() && i < r.structure.depth.size(); ++i)
    if (m.depths[i] != r.structure.depth[i])
      throw std::invalid_argument("interaction graph: depths disagree with the adjacency");
  if (m.depths.size() != r.structure.depth.size())
    throw std::invalid_argument("interaction graph: depths has the wrong size");
  r.mean_weights = m.mean_weights;
  r.held_out_loss = m.held_out_loss;
  return r;
}

}  // namespace srics::transport
