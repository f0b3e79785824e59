#include "learner/hac.h"

#include <algorithm>

#include "learner/acting_policy.h"

namespace srics::learner {
namespace {

// Goal replay's choice of goals among `count` candidates: k - 1 uniformly random ones and
// the last (fewer when there are fewer candidates), in increasing order.
std::vector<int> ReplayGoalIndices(int count, int k, std::mt19937_64& rng) {
  std::vector<int> indices;
  k = std::min(k, count);
  if (k <= 0) return indices;
  std::uniform_int_distribution<int> pick(0, count - 1);
  for (int i = 0; i < k - 1; ++i) indices.push_back(pick(rng));
  indices.push_back(count - 1);
  std::sort(indices.begin(), indices.end());
  return indices;
}

}  // namespace

HacTransitions BuildHacTransitions(const rl::Episode& e, const HacOptions& o, std::mt19937_64& rng) {
  const rl::EntityLayout& layout = e.layout;
  const int n = layout.num_entities;
  const auto segments = rl::HacSegments(e, o.horizon);
  const bool has_goal = e.goal.size() == static_cast<size_t>(2 * n);
  auto achieved = [&](int t) {
    std::vector<float> g(2 * n);
    rl::AchievedGoal(layout, e.state(t), g.data());
    return g;
  };
  auto reached = [&](int t, const float* goal) { return rl::GoalReached(layout, e.state(t), goal, o.threshold); };
  auto action_of = [&](const float* subgoal) {
    std::vector<float> a(2 * n);
    rl::ActionFromSubgoal(o.box, subgoal, n, a.data());
    return a;
  };
  // a transition t0 -> t1 towards `goal`: 0 and terminal when t1 reaches it, else -1
  auto make = [&](int t0, int t1, std::vector<float> goal, std::vector<float> action, HacRule rule) {
    HacTransition tr;
    tr.t0 = t0;
    tr.t1 = t1;
    tr.terminal = reached(t1, goal.data());
    tr.reward = tr.terminal ? 0.0f : -1.0f;
    tr.goal = std::move(goal);
    tr.action = std::move(action);
    tr.rule = rule;
    return tr;
  };
  HacTransitions out;

  // low level, attempt by attempt
  for (const rl::HacSegment& s : segments) {
    auto action = [&](int t) { return std::vector<float>(e.action(t), e.action(t) + e.action_dim); };
    if (s.index >= 0) {
      const float* subgoal = e.subgoal(s.index);
      for (int t = s.start; t < s.end; ++t)
        out.low.push_back(make(t, t + 1, {subgoal, subgoal + 2 * n}, action(t), HacRule::kHindsightAction));
    }
    for (int j : ReplayGoalIndices(s.end - s.start, o.hindsight_goals, rng)) {
      const std::vector<float> goal = achieved(s.start + j + 1);
      for (int t = s.start; t < s.end; ++t) out.low.push_back(make(t, t + 1, goal, action(t), HacRule::kHindsightGoal));
    }
  }

  // high level: the subgoal each attempt reached in hindsight (the proposed one if reached)
  std::vector<std::vector<float>> hindsight_actions;
  for (const rl::HacSegment& s : segments) {
    const float* subgoal = s.index >= 0 ? e.subgoal(s.index) : nullptr;
    const bool subgoal_reached = subgoal && reached(s.end, subgoal);
    hindsight_actions.push_back(subgoal_reached ? action_of(subgoal) : action_of(achieved(s.end).data()));
    if (!has_goal) continue;
    out.high.push_back(make(s.start, s.end, e.goal, hindsight_actions.back(), HacRule::kHindsightAction));
    if (subgoal && e.subgoal_tests[s.index] && !subgoal_reached) {
      HacTransition penalty;
      penalty.t0 = s.start;
      penalty.t1 = s.end;
      penalty.goal = e.goal;
      penalty.action = action_of(subgoal);
      penalty.reward = -static_cast<float>(o.horizon);
      penalty.terminal = true;
      penalty.rule = HacRule::kSubgoalTest;
      out.high.push_back(std::move(penalty));
    }
  }
  const int attempts = static_cast<int>(segments.size());
  for (int j : ReplayGoalIndices(attempts, o.hindsight_goals, rng)) {
    const std::vector<float> goal = achieved(segments[j].end);
    for (int k = 0; k < attempts; ++k)
      out.high.push_back(make(segments[k].start, segments[k].end, goal, hindsight_actions[k], HacRule::kHindsightGoal));
  }
  return out;
}

TransitionReplay::TransitionReplay(uint64_t capacity, int max_entities, int entity_dim, int goal_dim, int action_dim)
    : capacity_(std::max<uint64_t>(capacity, 1)),
      max_entities_(max_entities),
      entity_dim_(entity_dim),
      goal_dim_(goal_dim),
      action_dim_(action_dim),
      // state, next state, mask, goal, action, reward, terminal
      width_(2 * static_cast<size_t>(max_entities) * entity_dim + max_entities + goal_dim + action_dim + 2) {}

void TransitionReplay::Add(const rl::Episode& e, const HacTransition& tr) {
  if (size_ < capacity_ && records_.size() < (next_ + 1) * width_) records_.resize((next_ + 1) * width_);
  float* r = records_.data() + next_ * width_;
  std::fill(r, r + width_, 0.0f);
  const size_t states = static_cast<size_t>(max_entities_) * entity_dim_;
  std::copy_n(e.state(tr.t0), e.layout.state_size(), r);
  std::copy_n(e.state(tr.t1), e.layout.state_size(), r + states);
  std::fill_n(r + 2 * states, e.layout.num_entities, 1.0f);
  float* goal = r + 2 * states + max_entities_;
  std::copy(tr.goal.begin(), tr.goal.end(), goal);
  std::copy(tr.action.begin(), tr.action.end(), goal + goal_dim_);
  goal[goal_dim_ + action_dim_] = tr.reward;
  goal[goal_dim_ + action_dim_ + 1] = tr.terminal ? 1.0f : 0.0f;
  next_ = (next_ + 1) % capacity_;
  size_ = std::min(size_ + 1, capacity_);
}

void TransitionReplay::Sample(int size, std::mt19937_64& rng, TrainingBatch* b) const {
  const size_t states = static_cast<size_t>(max_entities_) * entity_dim_;
  b->size = size;
  b->max_entities = max_entities_;
  b->entity_dim = entity_dim_;
  b->goal_dim = goal_dim_;
  b->action_dim = action_dim_;
  b->entities.resize(size * states);
  b->next_entities.resize(size * states);
  b->mask.resize(static_cast<size_t>(size) * max_entities_);
  b->goal.resize(static_cast<size_t>(size) * goal_dim_);
  b->action.resize(static_cast<size_t>(size) * action_dim_);
  b->reward.resize(size);
  b->terminal.resize(size);
  b->subgoal_entity.assign(size, -1);
  std::uniform_int_distribution<uint64_t> pick(0, size_ - 1);
  for (int i = 0; i < size; ++i) {
    const float* r = records_.data() + pick(rng) * width_;
    std::copy_n(r, states, b->entities.begin() + i * states);
    std::copy_n(r + states, states, b->next_entities.begin() + i * states);
    std::copy_n(r + 2 * states, max_entities_, b->mask.begin() + static_cast<size_t>(i) * max_entities_);
    const float* goal = r + 2 * states + max_entities_;
    std::copy_n(goal, goal_dim_, b->goal.begin() + static_cast<size_t>(i) * goal_dim_);
    std::copy_n(goal + goal_dim_, action_dim_, b->action.begin() + static_cast<size_t>(i) * action_dim_);
    b->reward[i] = goal[goal_dim_ + action_dim_];
    b->terminal[i] = goal[goal_dim_ + action_dim_ + 1];
  }
}

void BoundHacTargets(const HacOptions& options, SacAgent* level) {
  if (options.bound_q) level->BoundTargets(-static_cast<float>(options.horizon), 0.0f);
}

HacLevels::HacLevels(const HacOptions& options, const rl::AgentShape& low, const rl::AgentShape& high,
                     const config::AgentConfig& agent, uint64_t capacity, int max_entities, uint64_t seed, int threads)
    : options_(options),
      high_(high, rl::HighLevelAgentConfig(agent, low, high), seed, threads),
      low_replay_(capacity, max_entities, low.entity_dim, low.goal_dim, low.action_dim),
      high_replay_(capacity, max_entities, high.entity_dim, high.goal_dim, high.action_dim),
      rng_(seed ^ 0x5bd1e995u) {
  BoundHacTargets(options, &high_);
}

void HacLevels::Add(const rl::Episode& episode) {
  const HacTransitions transitions = BuildHacTransitions(episode, options_, rng_);
  for (const HacTransition& t : transitions.low) low_replay_.Add(episode, t);
  for (const HacTransition& t : transitions.high) high_replay_.Add(episode, t);
}

UpdateStats HacLevels::Update(SacAgent& low, int batch_size) {
  high_replay_.Sample(batch_size, rng_, &batch_);
  last_high_ = high_.Update(batch_);
  const UpdateStats& high = last_high_;
  low_replay_.Sample(batch_size, rng_, &batch_);
  UpdateStats stats = low.Update(batch_);
  // the skipped stage of either level is reported (the high level's first: it runs first)
  if (high.non_finite) {
    stats.non_finite_stage =
        "high level: " + high.non_finite_stage + (stats.non_finite ? "; low level: " + stats.non_finite_stage : "");
    stats.non_finite = true;
  } else if (stats.non_finite) {
    stats.non_finite_stage = "low level: " + stats.non_finite_stage;
  }
  return stats;
}

std::vector<float> HacLevels::PolicyWeights(SacAgent& low) {
  std::vector<float> weights = high_.PolicyWeights();
  const std::vector<float> low_weights = low.PolicyWeights();
  weights.insert(weights.end(), low_weights.begin(), low_weights.end());
  return weights;
}

std::string HacLevels::PolicySignature(SacAgent& low) { return rl::HacPolicySignature(high_.policy(), low.policy()); }

void HacLevels::AppendCheckpointSections(const LearnerCounters& counters,
                                         std::vector<nn::CheckpointSection>* sections) {
  for (nn::CheckpointSection& s : high_.CheckpointSections(counters)) {
    s.name = kHacHighPrefix + s.name;
    sections->push_back(std::move(s));
  }
}

void HacLevels::LoadCheckpointSections(const std::vector<nn::CheckpointSection>& sections, const std::string& path) {
  std::vector<nn::CheckpointSection> high;
  const std::string prefix = kHacHighPrefix;
  for (const nn::CheckpointSection& s : sections)
    if (s.name.compare(0, prefix.size(), prefix) == 0) {
      high.push_back(s);
      high.back().name = s.name.substr(prefix.size());
    }
  if (high.empty()) throw nn::CheckpointError(path + ": no HAC high-level sections (" + prefix + "*)");
  high_.LoadCheckpointSections(high, path);
}

}  // namespace srics::learner
