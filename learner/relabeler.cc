#include "learner/relabeler.h"

#include <algorithm>
#include <stdexcept>

#include "common/rl/goal_token.h"
#include "common/rl/rewards.h"

namespace srics::learner {

Relabeler::Relabeler(config::Method method, const config::RewardConfig& reward, const config::RelabelConfig& relabel,
                     GoalRegion region, uint64_t seed, int goal_tokens)
    : method_(method), reward_(reward), relabel_(relabel), region_(region), rng_(seed), goal_tokens_(goal_tokens) {
  catalogue_.joint_ties = goal_tokens > 1;
}

void Relabeler::SetSubgoalStructure(const rl::SubgoalStructure& structure) {
  structure_ = structure;
  have_structure_ = true;
  catalogue_.graph.reset();
  by_kinds_.clear();
}

void Relabeler::SetGraph(const rl::InteractionGraph& catalogue) {
  catalogue_.graph = catalogue;
  have_structure_ = false;
  by_kinds_.clear();
}

const rl::SubgoalStructure* Relabeler::StructureOf(const rl::Episode& episode) {
  if (have_structure_) return &structure_;
  if (!catalogue_.graph) return nullptr;
  auto it = by_kinds_.find(episode.entity_kinds);
  if (it == by_kinds_.end()) {
    // stored episodes were validated against the run's catalogue; a kind outside the graph
    // (a graph of another run) leaves the episode without ancestors rather than throwing
    rl::SubgoalStructure structure;
    try {
      structure = catalogue_.For(episode.entity_kinds);
    } catch (const std::invalid_argument&) {
      structure = rl::CatalogueSubgoals{}.For(episode.entity_kinds);
    }
    it = by_kinds_.emplace(episode.entity_kinds, std::move(structure)).first;
  }
  return &it->second;
}

int Relabeler::PartnerOf(const rl::Episode& episode) {
  if (episode.subgoal_entity < 0) return -1;
  const rl::SubgoalStructure* structure = StructureOf(episode);
  return structure ? structure->partner_of(episode.subgoal_entity) : -1;
}

int Relabeler::PickSubgoalEntity(const rl::Episode& episode) {
  if (episode.subgoal_entity >= 0) return episode.subgoal_entity;
  // explore episodes carry no subgoal: pick one the current graph allows
  const rl::SubgoalStructure* structure = StructureOf(episode);
  const int n = episode.layout.num_entities;
  std::vector<int> candidates;
  if (structure) {  // (a pair once, by its first entity); entities beyond a fixed structure count too
    for (int i : structure->SubgoalEntities())
      if (i < n) candidates.push_back(i);
    for (int i = structure->num_entities(); i < n; ++i) candidates.push_back(i);
  } else {
    for (int i = 0; i < n; ++i) candidates.push_back(i);
  }
  if (candidates.empty()) candidates.push_back(0);
  return candidates[std::uniform_int_distribution<size_t>(0, candidates.size() - 1)(rng_)];
}

double Relabeler::Reward(const rl::Episode& e, const rl::SubgoalStructure* structure, int t,
                         const rl::SubgoalUnit& subgoal, const float* goal) const {
  const float* before = e.state(t);
  const float* after = e.state(t + 1);
  switch (method_) {
    case config::Method::kSacHer: return rl::FullGoalReward(e.layout, after, goal);
    case config::Method::kSrics: {
      const uint64_t ancestors = structure ? structure->AncestorsOf(subgoal) : 0;
      return rl::SelectivityReward(e.layout, before, after, subgoal, goal, ancestors, reward_);
    }
    default: return rl::DistanceReward(e.layout, after, subgoal, goal);
  }
}

void Relabeler::Sample(const ReplayBuffer& replay, int size, TrainingBatch* batch, std::vector<GoalSource>* sources) {
  // every stored episode shares one layout kind count; entity counts may differ
  const rl::EntityLayout& first = replay.contents().front().layout;
  const int n_max = replay.max_entities();
  const int d = first.entity_dim();
  const int k = first.num_kinds;
  const int a_dim = replay.contents().front().action_dim;
  batch->size = size;
  batch->max_entities = n_max;
  batch->entity_dim = d;
  batch->goal_dim = full_goal() ? 2 * n_max : goal_tokens_ * rl::SubgoalTokenSize(k);
  batch->action_dim = a_dim;
  batch->entities.assign(static_cast<size_t>(size) * n_max * d, 0.0f);
  batch->next_entities.assign(batch->entities.size(), 0.0f);
  batch->mask.assign(static_cast<size_t>(size) * n_max, 0.0f);
  batch->goal.assign(static_cast<size_t>(size) * batch->goal_dim, 0.0f);
  batch->action.resize(static_cast<size_t>(size) * a_dim);
  batch->reward.resize(size);
  batch->subgoal_entity.resize(size);
  if (sources) sources->resize(size);

  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> gx(region_.x_min, region_.x_max);
  std::uniform_real_distribution<double> gy(region_.y_min, region_.y_max);
  std::vector<float> goal;
  for (int b = 0; b < size; ++b) {
    const auto [episode, t] = replay.Sample(rng_);
    const rl::Episode& e = *episode;
    const int n = e.layout.num_entities;
    const int state_size = e.layout.state_size();
    std::copy_n(e.state(t), state_size, batch->entities.begin() + static_cast<size_t>(b) * n_max * d);
    std::copy_n(e.state(t + 1), state_size, batch->next_entities.begin() + static_cast<size_t>(b) * n_max * d);
    std::fill_n(batch->mask.begin() + static_cast<size_t>(b) * n_max, n, 1.0f);
    std::copy_n(e.action(t), a_dim, batch->action.begin() + static_cast<size_t>(b) * a_dim);

    const int entity = full_goal() ? -1 : PickSubgoalEntity(e);
    const rl::SubgoalStructure* structure = full_goal() ? nullptr : StructureOf(e);
    const rl::SubgoalUnit subgoal = structure ? structure->UnitOf(entity) : rl::SubgoalUnit(entity);
    const size_t goal_size = full_goal() ? 2 * n : 2 * subgoal.size();
    goal.resize(goal_size);
    // the original goal only exists when the episode was collected for this kind of goal
    const bool has_original = e.goal.size() == goal_size && e.subgoal_entity == entity;
    double u = unit(rng_);
    GoalSource source;
    if (u < relabel_.original && has_original) {
      source = GoalSource::kOriginal;
      std::copy(e.goal.begin(), e.goal.end(), goal.begin());
    } else if (u < relabel_.original + relabel_.future || (u < relabel_.original && !has_original)) {
      // a future state of the same entity (or of all entities) in the same episode
      source = GoalSource::kFuture;
      const int future = std::uniform_int_distribution<int>(t + 1, e.num_steps)(rng_);
      const float* s = e.state(future);
      if (full_goal()) {
        for (int j = 0; j < n; ++j) {
          goal[2 * j] = e.layout.x(s, j);
          goal[2 * j + 1] = e.layout.y(s, j);
        }
      } else {
        for (int m = 0; m < subgoal.size(); ++m) {
          goal[2 * m] = e.layout.x(s, subgoal.member(m));
          goal[2 * m + 1] = e.layout.y(s, subgoal.member(m));
        }
      }
    } else {
      source = GoalSource::kSampled;
      for (size_t j = 0; j < goal_size; j += 2) {
        goal[j] = static_cast<float>(gx(rng_));
        goal[j + 1] = static_cast<float>(gy(rng_));
      }
    }
    if (sources) (*sources)[b] = source;
    batch->reward[b] = static_cast<float>(Reward(e, full_goal() ? nullptr : structure, t, subgoal, goal.data()));
    batch->subgoal_entity[b] = entity;
    float* g = batch->goal.data() + static_cast<size_t>(b) * batch->goal_dim;
    if (full_goal()) {
      std::copy(goal.begin(), goal.end(), g);
    } else {
      rl::WriteSubgoalTokens(k, goal_tokens_, subgoal, e.entity_kinds, goal.data(), g);
    }
  }
}

}  // namespace srics::learner
