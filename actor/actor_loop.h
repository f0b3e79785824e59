#pragma once
// The actor's loop, with no transport in it: explore at random until a graph (for methods that
// use one) and first weights exist, then run training episodes on independently controllable
// subgoals with the latest weights (taken between episodes), holding back when the learner is
// too far behind; designated actors evaluate on a schedule. It talks to the rest of the
// system only through a links::ActorLink: DDS in the srics-actor process, the in-memory bus
// in `srics run --in-process`.
//
//   ActorLoop loop(ActorOptionsFor(config, rl::RunShapeFor(config), id, first_episode_id), &link);
//   loop.Run(stop);                       // or, to drive it by hand: while (loop.Step() != kDone)

#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "actor/eval_episode.h"
#include "actor/explore_episode.h"
#include "actor/train_episode.h"
#include "common/config/config.h"
#include "common/links/links.h"
#include "common/rl/agent_shape.h"
#include "common/rl/networks.h"

namespace srics::actor {

// Everything an actor needs, built from the run's config by ActorOptionsFor (the one place).
struct ActorOptions {
  uint32_t actor_id = 0;
  uint64_t first_episode_id = 0;  // a restarted actor continues its episode numbering
  uint64_t run_seed = 1;
  config::EnvConfig env;              // the environment this actor steps
  int num_entities = 0;               // the arm and every catalogue object (graphs are over these)
  rl::AttentionNetworkConfig policy;  // its policy network (the learner's signature must match)
  // HAC: the high level's network (`policy` is then the low level's); weights carry the high
  // level's parameters, then the low level's
  std::optional<rl::AttentionNetworkConfig> high_policy;
  bool uses_graph = true;  // false: every entity is a subgoal, no graph is awaited
  TrainOptions train;
  EvalOptions eval;
  ExploreOptions explore;  // how explore episodes act
  // explore episodes this actor contributes before it waits for the graph (its share of the
  // graph service's data set, with a margin)
  uint64_t explore_share = 0;
  // past its share, still one explore episode this often while the graph has not come
  // (episodes sent before the graph service listened are lost over DDS); 0 = never
  double explore_while_waiting_s = 1.0;
  bool evaluator = false;  // runs the evaluations of the run
  int eval_episodes = 20;
  uint64_t eval_every_env_steps = 5000;
  // rate limit: no more than rate_error_buffer updates' worth of data ahead of the learner
  double updates_per_step = 1;
  double rate_error_buffer = 0;
  uint64_t learner_warmup_steps = 0;  // while the learner refills its replay, never wait
  int rejected_log_interval_s = 5;    // refused weights and graphs are logged at most this often
  double status_period_s = 1;
};

ActorOptions ActorOptionsFor(const config::Config& config, const rl::RunShape& shape, uint32_t actor_id,
                             uint64_t first_episode_id = 0);

// The passive baseline (the hand never moves) on the run's evaluation goals, as the run's
// evaluating actors play it and publish it as policy version 0 (EvaluatePolicy without a
// policy, options.eval_episodes episodes of rl::EvalEpisodeSeed(options.run_seed, i)), played
// here without the run's graph: with no action nothing is pushed, so the distances, the success
// rate and the episode count do not depend on the subgoals or their order (selectivity and the
// attempt tallies do). Deterministic: what a recorder checks a received baseline against
// (issue 39: a stranger's v0 EvalResult became the run's baseline). A few seconds for a
// campaign config. Unstable episodes are left out (as the actor leaves them out).
rl::EvaluationSummary PlayPassiveBaseline(const ActorOptions& options);

struct ActorCounters {
  uint64_t env_steps = 0;
  uint64_t episodes = 0;
  uint64_t unstable_episodes = 0;
  uint64_t weights_rejected = 0;  // wrong architecture, size or magnitudes
  uint64_t graphs_rejected = 0;   // graph does not fit this environment
  // every refusal by counter (weights.architecture, weights.size, weights.magnitude,
  // graph.entities), reported in NodeStatus
  std::map<std::string, uint64_t> rejections;
  uint64_t evaluations = 0;
  uint64_t waits = 0;  // steps the rate limiter held the actor back
};

// What one Step did.
enum class StepResult {
  kWorked,  // ran an episode or an evaluation
  kIdle,    // waits for something (the graph, the learner): step again after new input
  kDone,    // the run's budget is done (after a final evaluation on an evaluator)
};

class ActorLoop {
 public:
  ActorLoop(ActorOptions options, links::ActorLink* link);
  ~ActorLoop();

  // One unit of work: takes what the link has (weights, graph, learner progress), then runs
  // at most one episode or one evaluation. Never blocks on the link.
  StepResult Step();

  // Steps until `stop` or kDone; waits on the link when idle. Returns 0 on a clean end.
  int Run(const std::atomic<bool>& stop);

  const ActorCounters& counters() const { return counters_; }
  uint64_t next_episode_id() const { return next_episode_id_; }
  // The environment this actor steps (for a recorder that draws it).
  env::Environment& environment();
  // Evaluations of a trained policy go through `recorder` (actors.record_eval_episodes).
  void set_eval_recorder(std::unique_ptr<EvalRecorder> recorder);
  uint64_t policy_version() const;
  uint64_t graph_version() const;

 private:
  struct State;
  void PollUpdates();
  bool Training() const;
  bool RateLimited();
  void Evaluate(bool passive);
  void RunEpisode(bool training);
  void Status(rl::NodePhase phase, const std::string& detail, bool force);
  void Refuse(const char* counter, const std::string& what);

  std::unique_ptr<State> state_;
  ActorOptions options_;
  links::ActorLink* link_;
  uint64_t next_episode_id_;
  ActorCounters counters_;
  std::unique_ptr<EvalRecorder> recorder_;
};

}  // namespace srics::actor
