#pragma once
// The actor's episode loops, with no DDS in them: exploration (random actions), training
// (one independently controllable subgoal per episode) and evaluation (a full goal split
// into subgoals, attempted in depth order). Shared by the actor process and the in-process
// trainer, so both behave the same.

#include <cstdint>
#include <optional>

#include "actor/env/environment.h"
#include "actor/env/scripted_policy.h"
#include "common/config/config.h"
#include "common/config/env_config.h"
#include "common/nn/tensor.h"
#include "common/rl/episode.h"
#include "common/rl/evaluation.h"
#include "common/rl/graph.h"
#include "common/rl/hac.h"
#include "common/rl/networks.h"

namespace srics::actor {

// The rl view of the environment's current layout.
rl::EntityLayout LayoutOf(const env::Environment& env);

// How explore episodes act (actors.explore_* of the config).
struct ExploreOptions {
  int steps = 50;
  double push_fraction = 0;               // share of episodes driven by the pushing controller
  int push_segment_steps = 10;            // steps per (object, target) pair
  double push_noise = 0.3;                // std of the Gaussian noise on each action component
  env::PushGeometry push;                 // hand and object geometry (the largest object of the table)
  env::Vec2 target_low{}, target_high{};  // targets are drawn in this box (the subgoal box)
};
ExploreOptions ExploreOptionsFor(const config::Config& config);

// Reset(seed), then `steps` steps of uniformly random actions or, for a push_fraction share
// of the episodes, of noisy pushes of random objects toward random targets. Empty if the
// physics became unstable (such an episode is never passed on).
std::optional<rl::Episode> RunExploreEpisode(env::Environment& env, const ExploreOptions& options, uint64_t seed,
                                             nn::Rng& rng);
// Uniformly random actions only.
std::optional<rl::Episode> RunExploreEpisode(env::Environment& env, int steps, uint64_t seed, nn::Rng& rng);

// How HAC's two levels act (agent.hac; the subgoal box from the table).
struct HacActOptions {
  int horizon = 20;               // H: low steps per subgoal at most, subgoals per training episode
  double test_probability = 0.3;  // a subgoal is tested (the low level acts without noise)
  double threshold = 0.05;        // a goal is reached with every entity this close
  rl::SubgoalBox box;
};

struct TrainOptions {
  int steps = 20;                    // episode length (HAC: the longest, H * H)
  bool full_goal = false;            // SAC+HER: the environment's full goal instead of a subgoal
  config::SamplingConfig sampling;   // subgoal goal region
  std::optional<HacActOptions> hac;  // set for HAC: two levels on the full goal
  int chain_episodes = 1;            // consecutive episodes per reset (actors.train_chain_episodes; not HAC)
};

// Where a training episode starts.
enum class TrainStart {
  kReset,          // a reset of the table with the episode's seed
  kWhereTheEnvIs,  // the state the last episode left (a chain: actors.train_chain_episodes)
};

// One training episode: a subgoal entity drawn uniformly among the subgoal entities of this
// episode's structure (subgoals.For the present entities' catalogue identities), its goal from the subgoal region,
// actions sampled from the policy. The episode records the subgoal, goal and ancestor mask. Empty if the physics became
// unstable.
std::optional<rl::Episode> RunTrainEpisode(env::Environment& env, rl::PolicyNetwork<float>& policy,
                                           const rl::CatalogueSubgoals& subgoals, const TrainOptions& options,
                                           uint64_t seed, nn::Rng& rng, TrainStart start = TrainStart::kReset);

// HAC's training episode: the high level proposes `horizon` subgoals (the xy of every entity)
// for the environment's full goal; the low level pursues each for `horizon` steps at most,
// ending early when it reaches the subgoal or the full goal. Each subgoal is a test subgoal
// with test_probability (the low level then takes its mean action). The episode records the
// full goal, the subgoals, where each started and which were tests. Empty if the physics
// became unstable.
std::optional<rl::Episode> RunHacTrainEpisode(env::Environment& env, rl::PolicyNetwork<float>& high,
                                              rl::PolicyNetwork<float>& low, const HacActOptions& options,
                                              uint64_t seed, nn::Rng& rng);

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
    double distance_after = 0;   // ... and when it ended
    // other subgoal objects (the arm, entity 0, left out: every push moves it) within the
    // threshold at the start, and how many of those ended the attempt outside it
    int others_solved = 0;
    int others_undone = 0;
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

// The options a run's config implies (episode lengths, full goal for SAC+HER and HAC, HAC's
// levels, subgoal order by method: depth for SRICS and its selectivity ablation, random
// otherwise).
HacActOptions HacActOptionsFor(const config::Config& config);
TrainOptions TrainOptionsFor(const config::Config& config);
EvalOptions EvalOptionsFor(const config::Config& config);

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
