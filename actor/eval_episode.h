#pragma once
// Evaluation episodes: the environment's own full goal, split into subgoals attempted on the
// method's schedule (SRICS, SMORL and the ablations), attempted whole (SAC+HER, the passive
// baseline's full goal) or by HAC's two levels; and the evaluation of a policy over a run's
// evaluation seeds.

#include <cstdint>
#include <optional>
#include <vector>

#include "actor/env/environment.h"
#include "actor/hac_acting.h"
#include "common/rl/evaluation.h"
#include "common/rl/graph.h"
#include "common/rl/networks.h"

namespace srics::actor {

struct EvalOptions {
  rl::SubgoalOrder order = rl::SubgoalOrder::kDepth;
  rl::EvaluationProtocol protocol = rl::EvaluationProtocol::kReference;
  int attempt_steps = 20;
  bool full_goal = false;            // SAC+HER and HAC: one attempt of (2N - 1) * attempt_steps on the full goal
  double threshold = 0.05;           // a subgoal counts as solved below this distance
  double epsilon = 1e-5;             // for the selectivity measure
  std::optional<HacActOptions> hac;  // HAC: the full-goal attempt runs both levels
};

// Sees an evaluation episode as it is played (`srics eval` draws it): once after the reset
// and once after every env step, so an episode of T steps is seen T + 1 times. Must not
// change the environment.
class EvalEpisodeObserver {
 public:
  virtual ~EvalEpisodeObserver() = default;
  // `entity`: the entity whose subgoal the step attempted; -1 after the reset and when the
  // episode attempts the full goal (SAC+HER, HAC, the passive policy's full goal).
  virtual void OnState(const env::Environment& env, int entity) = 0;

  // One scheduled subgoal attempt, once it is over (or skipped): what `srics eval` writes to
  // attempts.csv, to tell "cannot reach the subgoal" from "undoes the subgoals solved before".
  struct Attempt {
    int index = 0;  // position in the episode's schedule
    int entity = 0;
    bool skipped = false;        // already solved when its turn came (no steps taken)
    double distance_before = 0;  // the entity's distance to its goal when the attempt started
    double distance_after = 0;   // ... and when it ended (a tied pair attempted as one, by its
                                 // first entity: the farther of its two objects)
    // other subgoal objects (the arm, entity 0, left out: every push moves it) within the
    // threshold at the start, and how many of those ended the attempt outside it
    int others_solved = 0;
    int others_undone = 0;
    std::vector<int> solved_others;  // which entities others_solved counted, in index order
    // of others_undone, those that left the threshold before the attempted entity had moved
    // kMovedM from where it started: undone on the hand's way to it, while the selectivity
    // term (a ratio of the attempted entity's motion, at its floor while that is still) could
    // not tell knocking them from leaving them
    int others_undone_before_moved = 0;
    static constexpr double kMovedM = 0.01;
    // the same over the objects that are not the entity's ancestors in the structure the
    // episode uses (what selectivity asks to leave alone; every object without a graph)
    int independent_solved = 0;
    int independent_undone = 0;
    // every entity's distance to its goal when the attempt started and ended (how far a solved
    // object was pushed, not only whether it crossed the threshold)
    std::vector<double> distances_before, distances_after;
  };
  virtual void OnAttempt(const Attempt&) {}
};

// One evaluation episode on the environment's own goals (Reset(seed, kEval)). `policy` null
// is the passive baseline (it never moves). Deterministic policy (its mean action). For HAC
// (options.hac) `policy` is the low level and `high_policy` the high level, which proposes a
// subgoal whenever the low level has reached the last one or held it `horizon` steps.
// Returns the final-step metrics; empty if the physics became unstable. `observer` (may be
// null) sees every state of the episode.
std::optional<rl::EpisodeMetrics> RunEvaluationEpisode(env::Environment& env, rl::PolicyNetwork<float>* policy,
                                                       const rl::CatalogueSubgoals& subgoals,
                                                       const EvalOptions& options, uint64_t seed,
                                                       rl::PolicyNetwork<float>* high_policy = nullptr,
                                                       EvalEpisodeObserver* observer = nullptr);

// Draws some evaluation episodes (videos for people): Begin says whether episode `episode` of
// an evaluation of policy `policy_version` is recorded (its observer, or null); End follows
// every recorded episode with its metrics (empty: unstable). Implemented outside the actor
// library (actor/recording), so the loops need no renderer.
class EvalRecorder {
 public:
  virtual ~EvalRecorder() = default;
  virtual EvalEpisodeObserver* Begin(uint64_t policy_version, int episode, uint64_t seed) = 0;
  virtual void End(const std::optional<rl::EpisodeMetrics>& metrics, int steps) = 0;
};

// The evaluation protocol of every mode (actors, the in-process run, `srics eval`): `episodes`
// evaluation episodes with the run's evaluation seeds (rl::EvalEpisodeSeed: the same goals
// at every evaluation, for the policy and the passive baseline alike). Unstable episodes are
// left out of the summary and counted in *unstable.
rl::EvaluationSummary EvaluatePolicy(env::Environment& env, rl::PolicyNetwork<float>* policy,
                                     const rl::CatalogueSubgoals& subgoals, const EvalOptions& options, int episodes,
                                     uint64_t run_seed, uint64_t* unstable,
                                     rl::PolicyNetwork<float>* high_policy = nullptr, EvalRecorder* recorder = nullptr,
                                     uint64_t policy_version = 0);

}  // namespace srics::actor
