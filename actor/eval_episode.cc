#include "actor/eval_episode.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "actor/episode_parts.h"
#include "common/rl/goal_token.h"
#include "common/rl/rewards.h"
#include "common/rl/seeds.h"

namespace srics::actor {

namespace {

// One evaluation episode being played: the state every protocol shares (the observer, the
// deterministic policy's noise stream, the selectivity and compatibility sums), one method per
// protocol, and the final-step metrics.
class EvalEpisode {
 public:
  EvalEpisode(env::Environment& env, rl::PolicyNetwork<float>* policy, const rl::CatalogueSubgoals& subgoals,
              const EvalOptions& options, uint64_t seed, EvalEpisodeObserver* watcher)
      : env_(env),
        policy_(policy),
        options_(options),
        seed_(seed),
        watcher_(watcher),
        observer_(env),
        layout_(observer_.layout()),
        // the held-out combination's own structure, from the catalogue graph
        structure_(subgoals.For(env.layout().kinds)),
        episode_kinds_(env.layout().kinds.begin(), env.layout().kinds.end()),
        rng_(seed ^ 0x9e3779b97f4a7c15ull),
        zero_(env.action_dim(), 0.0f) {}

  // Steps of an attempt of the whole goal: (2N - 1) attempts' worth, N the entities.
  int FullGoalSteps() const { return (2 * layout_.num_entities - 1) * options_.attempt_steps; }

  // HAC: both levels, deterministic, for as many steps as a flat full-goal attempt.
  bool PlayHac(rl::PolicyNetwork<float>& high_policy) {
    const nn::Tensor goal = PaddedFullGoalToken(env_, high_policy.config().goal_dim);
    HacActor actor(high_policy, *policy_, *options_.hac, layout_, goal);
    observer_.Observe(env_);
    for (int t = 0; t < FullGoalSteps(); ++t) {
      if (actor.SubgoalOver(observer_.entities())) actor.Propose(observer_.entities(), true, false, rng_);
      if (!StepWith(env_, actor.Act(observer_.entities(), true, rng_).data(), env_.action_dim(), nullptr)) return false;
      if (watcher_) watcher_->OnState(env_, -1);
      observer_.Observe(env_);
    }
    return true;
  }

  // SAC+HER and the passive policy's full goal: one attempt of the whole goal.
  bool PlayFullGoal() { return Attempt(FullGoalToken(env_), rl::SubgoalUnit(), 0, FullGoalSteps()); }

  // The subgoal methods: the schedule of options.protocol and options.order (rl::AttemptSchedule),
  // each attempt recorded with the solved objects it began with and undid.
  bool PlaySubgoals() {
    std::mt19937_64 order_rng(seed_);
    // networks with two goal tokens attempt a tied pair as one (graph.object_ties: joint)
    const int tokens = policy_ ? policy_->config().goal_tokens : 1;
    nn::Tensor goal(1, tokens * rl::SubgoalTokenSize(layout_.num_kinds));
    // every entity with a subgoal, a pair's both objects too (SubgoalEntities lists a pair once)
    std::vector<int> subgoal_entities;
    for (int e = 0; e < structure_.num_entities(); ++e)
      if (structure_.has_subgoal(e)) subgoal_entities.push_back(e);
    int index = 0;
    rl::AttemptSchedule schedule(structure_, options_.order, options_.protocol, order_rng);
    std::vector<double> before_attempt;
    AttemptTrace trace;
    // a pair's distance: the farther of its two objects (both within the threshold: solved)
    auto farthest = [](const rl::SubgoalUnit& unit, const std::vector<double>& distances) {
      double d = 0;
      for (int m = 0; m < unit.size(); ++m) {
        const int e = unit.member(m);
        d = std::max(d, e < static_cast<int>(distances.size()) ? distances[e] : HUGE_VAL);
      }
      return d;
    };
    auto solved = [&](int entity) { return farthest(structure_.UnitOf(entity), before_attempt) < options_.threshold; };
    while (true) {
      before_attempt = env_.ComputeMetrics().distances;
      const std::optional<rl::AttemptSchedule::Slot> slot = schedule.Next(solved);
      if (!slot) break;
      const int entity = slot->entity;
      if (entity >= layout_.num_entities) continue;
      const rl::SubgoalUnit subgoal = structure_.UnitOf(entity);
      const uint64_t ancestors = structure_.AncestorsOf(subgoal);
      EvalEpisodeObserver::Attempt record;
      record.index = index++;
      record.entity = entity;
      record.distance_before = farthest(subgoal, before_attempt);
      record.skipped = slot->skipped;
      trace = AttemptTrace{};  // traced only for an observer (srics eval): a step's metrics cost
      if (!record.skipped) {
        if (policy_) {  // (the passive policy reads no goal)
          float xy[4];
          for (int m = 0; m < subgoal.size(); ++m) {
            const env::Vec2& g = env_.goals()[subgoal.member(m)];
            xy[2 * m] = static_cast<float>(g[0]);
            xy[2 * m + 1] = static_cast<float>(g[1]);
          }
          rl::WriteSubgoalTokens(layout_.num_kinds, tokens, subgoal, episode_kinds_, xy, goal.data());
        }
        if (!Attempt(goal, subgoal, ancestors, options_.attempt_steps, watcher_ ? &trace : nullptr)) return false;
      }
      const std::vector<double> after_attempt = record.skipped ? before_attempt : env_.ComputeMetrics().distances;
      record.distance_after = farthest(subgoal, after_attempt);
      record.distances_before = before_attempt;
      record.distances_after = after_attempt;
      for (int other : subgoal_entities) {
        if (subgoal.contains(other) || other == 0 || other >= layout_.num_entities ||
            before_attempt[other] >= options_.threshold)
          continue;
        const bool undone = after_attempt[other] >= options_.threshold;
        ++record.others_solved;
        record.others_undone += undone ? 1 : 0;
        record.solved_others.push_back(other);
        if (undone && trace.LeftBeforeTheEntityMoved(other)) ++record.others_undone_before_moved;
        if ((ancestors >> other) & 1u) continue;
        ++record.independent_solved;
        record.independent_undone += undone ? 1 : 0;
      }
      if (!record.skipped) {  // a slot used up without steps undoes nothing: not counted
        independent_solved_ += record.independent_solved;
        independent_undone_ += record.independent_undone;
      }
      if (watcher_) watcher_->OnAttempt(record);
    }
    return true;
  }

  // The final step's metrics, with the selectivity and compatibility the attempts measured.
  rl::EpisodeMetrics Metrics() const {
    const env::Metrics m = env_.ComputeMetrics();
    rl::EpisodeMetrics out;
    out.entity_distance = m.distances;
    out.avg_distance = m.avg_distance;
    out.avg_object_distance = m.avg_object_distance;
    out.success = m.success;
    out.selectivity = selectivity_steps_ ? selectivity_sum_ / selectivity_steps_ : -1.0;
    out.independent_solved = independent_solved_;
    out.independent_undone = independent_undone_;
    return out;
  }

 private:
  // When, within one subgoal attempt, the attempted entity first stood kMovedM from where it
  // began, and each entity first stood at or beyond the threshold from its goal (steps from 1;
  // 0: not within the attempt).
  struct AttemptTrace {
    int entity_moved_at = 0;
    std::vector<int> left_threshold_at;
    bool LeftBeforeTheEntityMoved(int other) const {
      const int left = other < static_cast<int>(left_threshold_at.size()) ? left_threshold_at[other] : 0;
      return left > 0 && (entity_moved_at == 0 || left < entity_moved_at);
    }
  };

  // One attempt: `steps` steps towards `goal` (a token), measuring selectivity for `subgoal`
  // (entity -1: the full goal, not measured) against the motion outside it and `ancestors`,
  // and, with `trace`, when what moved. False when the physics became unstable.
  bool Attempt(const nn::Tensor& goal, const rl::SubgoalUnit& subgoal, uint64_t ancestors, int steps,
               AttemptTrace* trace = nullptr) {
    const int entity = subgoal.entity;
    std::vector<env::Vec2> start;
    if (trace) {
      start = env_.Positions();
      trace->left_threshold_at.assign(start.size(), 0);
    }
    for (int t = 0; t < steps; ++t) {
      observer_.Observe(env_);
      before_.assign(observer_.entities().data(), observer_.entities().data() + observer_.entities().size());
      const float* action = policy_ ? policy_->Act(observer_.entities(), goal, true, rng_).data() : zero_.data();
      if (!StepWith(env_, action, env_.action_dim(), nullptr)) return false;
      if (watcher_) watcher_->OnState(env_, entity);
      if (trace) Trace(entity, start, t + 1, trace);
      if (entity >= 0) {
        const nn::Tensor& after = observer_.Observe(env_);
        if (auto m =
                rl::SelectivityMeasure(layout_, before_.data(), after.data(), subgoal, ancestors, options_.epsilon)) {
          selectivity_sum_ += *m;
          ++selectivity_steps_;
        }
      }
    }
    return true;
  }

  void Trace(int entity, const std::vector<env::Vec2>& start, int step, AttemptTrace* trace) const {
    if (trace->entity_moved_at == 0) {
      const env::Vec2 now = env_.Positions()[entity];
      if (std::hypot(now[0] - start[entity][0], now[1] - start[entity][1]) >= EvalEpisodeObserver::Attempt::kMovedM)
        trace->entity_moved_at = step;
    }
    const std::vector<double> distances = env_.ComputeMetrics().distances;
    for (size_t e = 0; e < distances.size() && e < trace->left_threshold_at.size(); ++e)
      if (trace->left_threshold_at[e] == 0 && distances[e] >= options_.threshold) trace->left_threshold_at[e] = step;
  }

  env::Environment& env_;
  rl::PolicyNetwork<float>* policy_;
  const EvalOptions& options_;
  uint64_t seed_;
  EvalEpisodeObserver* watcher_;
  Observer observer_;
  rl::EntityLayout layout_;
  rl::SubgoalStructure structure_;
  std::vector<uint16_t> episode_kinds_;  // catalogue kind of each entity
  nn::Rng rng_;
  std::vector<float> zero_;
  std::vector<float> before_;
  double selectivity_sum_ = 0;
  int selectivity_steps_ = 0;
  int independent_solved_ = 0, independent_undone_ = 0;
};

}  // namespace

std::optional<rl::EpisodeMetrics> RunEvaluationEpisode(env::Environment& env, rl::PolicyNetwork<float>* policy,
                                                       const rl::CatalogueSubgoals& subgoals,
                                                       const EvalOptions& options, uint64_t seed,
                                                       rl::PolicyNetwork<float>* high_policy,
                                                       EvalEpisodeObserver* watcher) {
  env.Reset(seed, env::Split::kEval);
  if (watcher) watcher->OnState(env, -1);
  EvalEpisode episode(env, policy, subgoals, options, seed, watcher);
  bool stable = true;
  if (options.hac && policy) {
    if (!high_policy) throw std::invalid_argument("HAC evaluation needs the high-level policy");
    stable = episode.PlayHac(*high_policy);
  } else if (options.full_goal) {
    stable = episode.PlayFullGoal();
  } else {
    stable = episode.PlaySubgoals();
  }
  if (!stable) return std::nullopt;
  return episode.Metrics();
}

rl::EvaluationSummary EvaluatePolicy(env::Environment& env, rl::PolicyNetwork<float>* policy,
                                     const rl::CatalogueSubgoals& subgoals, const EvalOptions& options, int episodes,
                                     uint64_t run_seed, uint64_t* unstable, rl::PolicyNetwork<float>* high_policy,
                                     EvalRecorder* recorder, uint64_t policy_version) {
  rl::EvaluationSummary summary;
  for (int i = 0; i < episodes; ++i) {
    const uint64_t seed = rl::EvalEpisodeSeed(run_seed, i);
    EvalEpisodeObserver* observer = recorder ? recorder->Begin(policy_version, i, seed) : nullptr;
    const auto metrics = RunEvaluationEpisode(env, policy, subgoals, options, seed, high_policy, observer);
    if (observer) recorder->End(metrics, env.steps());
    if (metrics)
      summary.Add(*metrics, options.threshold);
    else
      ++*unstable;
  }
  return summary;
}

}  // namespace srics::actor
