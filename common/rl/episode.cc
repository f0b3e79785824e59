#include "common/rl/episode.h"

#include <cmath>

namespace srics::rl {
namespace {

bool AllFinite(const std::vector<float>& values) {
  for (float v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace

std::string ValidateEpisode(const Episode& e) {
  const EntityLayout& l = e.layout;
  if (l.num_entities < 1 || l.num_entities > 64) return "num_entities outside [1, 64]";
  if (l.num_kinds < 1 || l.num_kinds > 64) return "num_kinds outside [1, 64]";
  if (e.num_steps < 1 || e.num_steps > 100000) return "num_steps outside [1, 100000]";
  if (e.action_dim < 1 || e.action_dim > 64) return "action_dim outside [1, 64]";
  if (e.entity_kinds.size() != static_cast<size_t>(l.num_entities))
    return "entity_kinds has " + std::to_string(e.entity_kinds.size()) + " entries for " +
           std::to_string(l.num_entities) + " entities";
  for (uint16_t kind : e.entity_kinds)
    if (kind >= l.num_kinds) return "entity kind " + std::to_string(kind) + " >= num_kinds";
  const size_t states = static_cast<size_t>(e.num_steps + 1) * l.state_size();
  if (e.states.size() != states)
    return "states has " + std::to_string(e.states.size()) + " floats, expected " + std::to_string(states);
  const size_t actions = static_cast<size_t>(e.num_steps) * e.action_dim;
  if (e.actions.size() != actions)
    return "actions has " + std::to_string(e.actions.size()) + " floats, expected " + std::to_string(actions);
  if (e.subgoal_entity < -1 || e.subgoal_entity >= l.num_entities) return "subgoal entity out of range";
  if (e.subgoal_entity >= 0 && e.goal.size() != 2) return "a subgoal needs a goal of 2 floats";
  if (e.subgoal_entity < 0 && !e.goal.empty() && e.goal.size() != 2u * l.num_entities)
    return "a full goal needs 2N floats";
  if (l.num_entities < 64 && (e.ancestor_mask >> l.num_entities) != 0) return "ancestor mask names missing entities";
  if (!AllFinite(e.states)) return "states contain NaN or infinity";
  if (!AllFinite(e.actions)) return "actions contain NaN or infinity";
  if (!AllFinite(e.goal)) return "goal contains NaN or infinity";
  for (float a : e.actions)
    if (a < -1.0f || a > 1.0f) return "an action lies outside [-1, 1]";
  return "";
}

}  // namespace srics::rl
