#include "actor/actor_loop.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "actor/env/rearrange_env.h"
#include "actor/episode_options.h"
#include "common/logging/logging.h"
#include "common/nn/serialize.h"
#include "common/profile/phase_clock.h"
#include "common/rl/agent_shape.h"
#include "common/rl/seeds.h"

namespace srics::actor {

using Clock = std::chrono::steady_clock;

ActorOptions ActorOptionsFor(const config::Config& config, const rl::RunShape& shape, uint32_t actor_id,
                             uint64_t first_episode_id) {
  ActorOptions o;
  o.actor_id = actor_id;
  o.first_episode_id = first_episode_id;
  o.run_seed = config.run.seed;
  o.env = config.env;
  o.num_entities = shape.entities();
  o.policy = rl::MakeNetworkConfig(shape.agent, config.agent);
  if (config.run.method == config::Method::kHac) o.high_policy = rl::MakeNetworkConfig(shape.high, config.agent);
  o.uses_graph = rl::UsesGraph(config.run.method);
  o.train = TrainOptionsFor(config, shape);
  o.eval = EvalOptionsFor(config, shape);
  o.explore = ExploreOptionsFor(config);
  o.explore_share = static_cast<uint64_t>(std::ceil(1.2 * config.graph.episodes / std::max(1, config.actors.count)));
  o.evaluator = static_cast<int>(actor_id) < config.actors.evaluators;
  o.eval_episodes = config.actors.eval_episodes;
  o.eval_every_env_steps = config.actors.eval_every_env_steps;
  o.updates_per_step = config.learner.updates_per_step;
  o.rate_error_buffer = config.learner.rate_error_buffer;
  o.learner_warmup_steps = config.learner.warmup_steps;
  o.status_period_s = config.transport.status_period_s;
  o.rejected_log_interval_s = config.transport.rejected_log_interval_s;
  return o;
}

rl::EvaluationSummary PlayPassiveBaseline(const ActorOptions& options) {
  const std::unique_ptr<env::Environment> env = env::MakeRearrangeEnv(options.env);
  uint64_t unstable = 0;
  return EvaluatePolicy(*env, nullptr, rl::CatalogueSubgoals{}, options.eval, options.eval_episodes, options.run_seed,
                        &unstable);
}

struct ActorLoop::State {
  std::unique_ptr<env::Environment> env;
  std::unique_ptr<rl::PolicyNetwork<float>> policy;
  std::unique_ptr<rl::PolicyNetwork<float>> high;  // HAC's high level, else null
  std::string signature;
  int num_entities = 0;  // the catalogue's (arm + every object): the size of the run's graphs
  nn::Rng rng;
  bool have_weights = false;
  // training episodes of the current chain so far (actors.train_chain_episodes): the next one
  // starts where the last left the table while this is above 0
  int chain_played = 0;
  uint64_t policy_version = 0;
  bool have_graph = false;
  uint64_t graph_version = 0;
  rl::CatalogueSubgoals subgoals;  // each episode maps it onto the objects it presents
  std::optional<rl::LearnerProgress> learner;
  bool passive_evaluated = false;
  uint64_t evaluated_version = 0;  // policy version of the last evaluation
  uint64_t next_eval_steps = 0;
  bool final_poll_done = false;  // one more look for the final weights before the last evaluation
  Clock::time_point last_status;
  Clock::time_point last_episode_end;
  std::unique_ptr<logging::RateLimiter> refusals_log;
};

ActorLoop::ActorLoop(ActorOptions options, links::ActorLink* link)
    : state_(std::make_unique<State>()),
      options_(std::move(options)),
      link_(link),
      next_episode_id_(options_.first_episode_id) {
  State& s = *state_;
  s.env = env::MakeRearrangeEnv(options_.env);
  // graphs are over the catalogue, whichever objects an episode presents
  s.num_entities = options_.num_entities;
  s.rng.seed(
      rl::DeriveSeed(options_.run_seed, rl::SeedPurpose::kActorRng, options_.actor_id, options_.first_episode_id));
  s.policy = std::make_unique<rl::PolicyNetwork<float>>("policy", options_.policy, s.rng);
  if (options_.high_policy) s.high = std::make_unique<rl::PolicyNetwork<float>>("policy", *options_.high_policy, s.rng);
  s.signature = s.high ? rl::HacPolicySignature(*s.high, *s.policy) : rl::PolicySignature(*s.policy);
  if (!options_.uses_graph) {
    s.have_graph = true;  // no graph: every present entity is a subgoal
  }
  s.subgoals.joint_ties = options_.policy.goal_tokens > 1;  // the networks take a pair's two tokens
  if (options_.evaluator && options_.eval_every_env_steps == 0)
    throw std::invalid_argument("actor " + std::to_string(options_.actor_id) +
                                ": eval_every_env_steps must be positive (actors.eval_every_env_steps)");
  s.next_eval_steps = options_.eval_every_env_steps;
  s.refusals_log = std::make_unique<logging::RateLimiter>(std::chrono::seconds(options_.rejected_log_interval_s));
}

ActorLoop::~ActorLoop() = default;

uint64_t ActorLoop::policy_version() const { return state_->policy_version; }
uint64_t ActorLoop::graph_version() const { return state_->graph_version; }

bool ActorLoop::Training() const { return state_->have_weights && state_->have_graph; }

void ActorLoop::Status(rl::NodePhase phase, const std::string& detail, bool force) {
  State& s = *state_;
  if (!force && std::chrono::duration<double>(Clock::now() - s.last_status).count() < options_.status_period_s) return;
  s.last_status = Clock::now();
  rl::NodeReport r;
  r.phase = phase;
  r.policy_version = s.policy_version;
  r.graph_version = s.graph_version;
  r.steps = counters_.env_steps;
  r.dropped = counters_.weights_rejected + counters_.graphs_rejected;
  r.rejections = counters_.rejections;
  r.detail = detail;
  link_->PublishStatus(r);
}

void ActorLoop::Refuse(const char* counter, const std::string& what) {
  ++counters_.rejections[counter];
  uint64_t suppressed = 0;
  if (state_->refusals_log->Allow(&suppressed))
    spdlog::warn("{}: ignored ({}; {} warnings suppressed)", what, counter, suppressed);
}

void ActorLoop::PollUpdates() {
  State& s = *state_;
  if (auto g = link_->PollGraph()) {
    if (const std::string problem = rl::GraphMismatch(g->graph, s.num_entities); !problem.empty()) {
      ++counters_.graphs_rejected;
      Refuse("graph.entities", "graph v" + std::to_string(g->version) + ": " + problem);
    } else if (options_.uses_graph) {
      s.subgoals.graph = g->graph;
      s.have_graph = true;
      s.graph_version = g->version;
      spdlog::info("graph v{}: {}", g->version, rl::DescribeGraph(g->graph));
    }
  }
  // weights are checked against this actor's network before anything changes: a refused
  // sample leaves the version (and so the next good weights) as they were
  if (auto w = link_->PollWeights(s.have_weights ? s.policy_version : 0)) {
    auto params = s.policy->Parameters();
    const int64_t high_size = s.high ? nn::NumScalars(s.high->Parameters()) : 0;
    const std::string what = "weights v" + std::to_string(w->version);
    std::string problem;
    if (w->architecture != s.signature) {
      ++counters_.weights_rejected;
      Refuse("weights.architecture", what + " are for " + w->architecture + ", this actor's network is " + s.signature);
    } else if (static_cast<int64_t>(w->parameters.size()) != high_size + nn::NumScalars(params)) {
      ++counters_.weights_rejected;
      Refuse("weights.size", what + " have " + std::to_string(w->parameters.size()) + " parameters, this network " +
                                 std::to_string(high_size + nn::NumScalars(params)));
    } else if (problem = rl::ParameterProblem(w->parameters); !problem.empty()) {
      ++counters_.weights_rejected;
      Refuse("weights.magnitude", what + ": " + problem);
    } else {
      // HAC: the high level's parameters first, then the low level's
      const std::span<const float> flat(w->parameters);
      if (s.high) nn::LoadFlat(s.high->Parameters(), flat.first(high_size));
      nn::LoadFlat(params, flat.subspan(high_size));
      if (!s.have_weights) spdlog::info("first weights: v{}", w->version);
      s.have_weights = true;
      s.policy_version = w->version;
    }
  }
  if (auto p = link_->PollLearner(std::chrono::milliseconds(0))) s.learner = p;
}

// The learner's own rate limit decides: it reports the updates it owes the data it counts
// (LearnerStats.update_backlog), and every actor holds back while that is above the error
// buffer. A learner that cannot update (warm-up, refilling after a restart, no graph yet)
// reports 0, so nobody waits for it then. Actors used to estimate the backlog from where each
// had started counting: the learner's limiter does not count the warm-up's transitions nor
// those that came while it waited for the graph, so an actor counting from before that ended
// waited for ever (issue 15), and actors that started counting at different moments disagreed
// (the one that started at the larger lag took every allowance: 182,100 env steps against
// 32,800 in an in-process campaign run).
bool ActorLoop::RateLimited() {
  State& s = *state_;
  if (options_.updates_per_step <= 0 || !s.learner) return false;
  const rl::LearnerProgress& now = *s.learner;
  if (now.replay_size < options_.learner_warmup_steps || now.budget_done()) return false;
  return now.update_backlog > options_.rate_error_buffer;
}

env::Environment& ActorLoop::environment() { return *state_->env; }

void ActorLoop::set_eval_recorder(std::unique_ptr<EvalRecorder> recorder) { recorder_ = std::move(recorder); }

void ActorLoop::Evaluate(bool passive) {
  state_->chain_played = 0;  // an evaluation resets the table: the chain ends
  profile::PhaseScope phase(profile::Phase::kEvaluation);
  State& s = *state_;
  Status(rl::NodePhase::kEvaluating, passive ? "passive baseline" : "evaluating", true);
  rl::EvalReport report;
  report.actor_id = options_.actor_id;
  report.policy_version = passive ? 0 : s.policy_version;
  report.graph_version = s.graph_version;
  report.env_steps = s.learner ? s.learner->training_env_steps : 0;
  report.summary = EvaluatePolicy(*s.env, passive ? nullptr : s.policy.get(), s.subgoals, options_.eval,
                                  options_.eval_episodes, options_.run_seed, &counters_.unstable_episodes, s.high.get(),
                                  passive ? nullptr : recorder_.get(), s.policy_version);
  ++counters_.evaluations;
  if (!passive) s.evaluated_version = s.policy_version;
  link_->PublishEval(report);
  // which catalogue entities the (last) evaluation episode presented: with eval_object_sets the
  // held-out combination, visible in the log
  std::string present;
  for (int kind : s.env->layout().kinds) present += (present.empty() ? "" : ", ") + std::to_string(kind);
  spdlog::info(
      "evaluation ({}) at {} env steps on catalogue entities [{}]: avg_object_distance {:.4f}, "
      "avg_distance {:.4f}, success {:.2f}",
      passive ? "passive" : "policy v" + std::to_string(s.policy_version), report.env_steps, present,
      report.summary.avg_object_distance, report.summary.avg_distance, report.summary.success_rate);
}

void ActorLoop::RunEpisode(bool training) {
  State& s = *state_;
  const uint64_t seed =
      rl::DeriveSeed(options_.run_seed, rl::SeedPurpose::kEpisode, options_.actor_id, next_episode_id_);
  std::optional<rl::Episode> episode;
  if (training) {
    Status(rl::NodePhase::kTraining, "", false);
    if (s.high) {
      episode = RunHacTrainEpisode(*s.env, *s.high, *s.policy, *options_.train.hac, seed, s.rng);
    } else {
      const TrainStart start = s.chain_played > 0 ? TrainStart::kWhereTheEnvIs : TrainStart::kReset;
      episode = RunTrainEpisode(*s.env, *s.policy, s.subgoals, options_.train, seed, s.rng, start);
      s.chain_played = episode ? (s.chain_played + 1) % std::max(1, options_.train.chain_episodes) : 0;
    }
  } else {
    s.chain_played = 0;
    Status(rl::NodePhase::kExploring, s.have_graph ? "waiting for weights" : "waiting for the graph", false);
    episode = RunExploreEpisode(*s.env, options_.explore, seed, s.rng);
  }
  const uint64_t id = next_episode_id_++;
  s.last_episode_end = Clock::now();
  if (!episode) {
    ++counters_.unstable_episodes;
    spdlog::warn("episode {} became physically unstable: dropped", id);
    return;
  }
  episode->actor_id = options_.actor_id;
  episode->episode_id = id;
  episode->policy_version = training ? s.policy_version : 0;
  episode->graph_version = s.graph_version;
  if (!link_->PublishEpisode(*episode)) return;
  counters_.env_steps += episode->num_steps;
  ++counters_.episodes;
}

StepResult ActorLoop::Step() {
  State& s = *state_;
  PollUpdates();
  const bool training = Training();

  if (s.learner && s.learner->budget_done()) {
    // the learner has all the data it wants: a last evaluation with the final weights, after
    // one more look for them (they are published just before the budget-done stats)
    if (options_.evaluator && training) {
      if (!s.final_poll_done) {
        s.final_poll_done = true;
        return StepResult::kIdle;
      }
      if (s.policy_version != s.evaluated_version) Evaluate(false);
    }
    Status(rl::NodePhase::kStopping, "budget done", true);
    return StepResult::kDone;
  }
  if (options_.evaluator && training) {
    if (!s.passive_evaluated) {
      s.passive_evaluated = true;
      Evaluate(true);
      return StepResult::kWorked;
    }
    if (s.learner && s.learner->training_env_steps >= s.next_eval_steps) {
      // the next multiple of the interval above the learner's steps, in one step (a loop would
      // run for as long as the reported step count is large)
      const uint64_t every = std::max<uint64_t>(1, options_.eval_every_env_steps);
      s.next_eval_steps = (s.learner->training_env_steps / every + 1) * every;
      Evaluate(false);
      return StepResult::kWorked;
    }
  }
  // beyond its share of the graph's data this actor waits for the graph, leaving the CPU to
  // the GNN and the replay to useful data
  if (!training && !s.have_graph && counters_.episodes >= options_.explore_share) {
    const bool feed =
        options_.explore_while_waiting_s > 0 &&
        std::chrono::duration<double>(Clock::now() - s.last_episode_end).count() >= options_.explore_while_waiting_s;
    if (!feed) {
      Status(rl::NodePhase::kWaiting, "waiting for the graph (exploration share done)", false);
      return StepResult::kIdle;
    }
  }
  if (training && RateLimited()) {
    ++counters_.waits;
    Status(rl::NodePhase::kWaiting, "waiting for the learner", false);
    return StepResult::kIdle;
  }
  RunEpisode(training);
  return StepResult::kWorked;
}

int ActorLoop::Run(const std::atomic<bool>& stop) {
  Status(rl::NodePhase::kStarting, "", true);
  while (!stop) {
    const StepResult result = Step();
    if (result == StepResult::kDone) return 0;
    if (result == StepResult::kIdle) {
      // block on the link for news instead of spinning (the learner's stats come often)
      if (auto p = link_->PollLearner(std::chrono::milliseconds(200))) state_->learner = p;
    }
  }
  Status(rl::NodePhase::kStopping, "stopped", true);
  return 0;
}

}  // namespace srics::actor
