#include "actor/actor_loop.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <thread>

#include "actor/env/rearrange_env.h"
#include "actor/rollout.h"
#include "common/nn/serialize.h"
#include "common/rl/agent_shape.h"
#include "common/rl/networks.h"

namespace srics::actor {

using Clock = std::chrono::steady_clock;

struct ActorLoop::State {
  std::unique_ptr<env::Environment> env;
  std::unique_ptr<rl::PolicyNetwork<float>> policy;
  std::string signature;
  nn::Rng rng;
  bool have_weights = false;
  uint64_t policy_version = 0;
  bool have_graph = false;
  uint64_t graph_version = 0;
  rl::SubgoalStructure structure;
  std::optional<rl::LearnerProgress> learner;
  // learner progress when this actor started training: rate limiting counts from there
  std::optional<rl::LearnerProgress> baseline;
  bool passive_evaluated = false;
  uint64_t evaluated_version = 0;  // policy version of the last evaluation
  uint64_t next_eval_steps = 0;
  Clock::time_point last_status;
};

ActorLoop::ActorLoop(const config::Config& config, uint32_t actor_id, ActorLink* link,
                     uint64_t first_episode_id)
    : state_(std::make_unique<State>()),
      config_(config),
      actor_id_(actor_id),
      link_(link),
      next_episode_id_(first_episode_id) {
  State& s = *state_;
  s.env = env::MakeRearrangeEnv(config.env);
  s.rng.seed(config.run.seed * 6364136223846793005ull + actor_id * 1442695040888963407ull + first_episode_id);
  const rl::AgentShape shape = rl::AgentShapeFor(config.env, config.run.method);
  s.policy = std::make_unique<rl::PolicyNetwork<float>>("policy", rl::MakeNetworkConfig(shape, config.agent), s.rng);
  s.signature = rl::PolicySignature(*s.policy);
  const int n = 1 + static_cast<int>(config::EffectiveObjects(config.env).size());
  if (!rl::UsesGraph(config.run.method)) {
    s.structure = rl::AllEntitiesStructure(n);
    s.have_graph = true;
  }
  s.next_eval_steps = config.actors.eval_every_env_steps;
}

ActorLoop::~ActorLoop() = default;

int ActorLoop::Run(const std::atomic<bool>& stop) {
  State& s = *state_;
  const config::Config& c = config_;
  const bool evaluator = static_cast<int>(actor_id_) < c.actors.evaluators;
  const int num_entities = 1 + static_cast<int>(config::EffectiveObjects(c.env).size());
  const config::Method method = c.run.method;

  const TrainOptions train = TrainOptionsFor(c);
  const EvalOptions eval = EvalOptionsFor(c);

  auto status = [&](rl::NodePhase phase, const std::string& detail, bool force) {
    if (!force && std::chrono::duration<double>(Clock::now() - s.last_status).count() < c.transport.status_period_s)
      return;
    s.last_status = Clock::now();
    rl::NodeReport r;
    r.phase = phase;
    r.policy_version = s.policy_version;
    r.graph_version = s.graph_version;
    r.steps = counters_.env_steps;
    r.dropped = counters_.weights_rejected + counters_.graphs_rejected;
    r.detail = detail;
    link_->PublishStatus(r);
  };

  auto poll_updates = [&]() {
    if (auto g = link_->PollGraph()) {
      if (g->graph.num_entities != num_entities) {
        ++counters_.graphs_rejected;
        spdlog::warn("graph v{} has {} entities, this environment has {}: ignored", g->version,
                     g->graph.num_entities, num_entities);
      } else if (rl::UsesGraph(method)) {
        s.structure = g->structure;
        s.have_graph = true;
        s.graph_version = g->version;
        spdlog::info("graph v{}: {}", g->version, rl::DescribeGraph(g->graph));
      }
    }
    if (auto w = link_->PollWeights()) {
      auto params = s.policy->Parameters();
      if (w->architecture != s.signature || static_cast<int64_t>(w->parameters.size()) != nn::NumScalars(params)) {
        ++counters_.weights_rejected;
        spdlog::warn("weights v{} ({}, {} floats) do not fit this actor's network ({}): ignored",
                     w->version, w->architecture, w->parameters.size(), s.signature);
      } else {
        nn::LoadFlat(params, w->parameters);
        if (!s.have_weights) spdlog::info("first weights: v{}", w->version);
        s.have_weights = true;
        s.policy_version = w->version;
      }
    }
    if (auto p = link_->PollLearner(std::chrono::milliseconds(0))) s.learner = p;
  };

  auto budget_done = [&]() { return s.learner && s.learner->budget_done(); };

  auto evaluate = [&](bool passive) {
    status(rl::NodePhase::kEvaluating, passive ? "passive baseline" : "evaluating", true);
    rl::EvalReport report;
    report.actor_id = actor_id_;
    report.policy_version = passive ? 0 : s.policy_version;
    report.graph_version = s.graph_version;
    report.env_steps = s.learner ? s.learner->training_env_steps : 0;
    for (int i = 0; i < c.actors.eval_episodes && !stop; ++i) {
      auto m = RunEvaluationEpisode(*s.env, passive ? nullptr : s.policy.get(), s.structure, eval,
                                    EvalSeed(c.run.seed, i));
      if (m) report.summary.Add(*m, eval.threshold);
      else ++counters_.unstable_episodes;
    }
    if (stop) return;
    ++counters_.evaluations;
    if (!passive) s.evaluated_version = s.policy_version;
    link_->PublishEval(report);
    spdlog::info("evaluation ({}) at {} env steps: avg_object_distance {:.4f}, avg_distance {:.4f}, success {:.2f}",
                 passive ? "passive" : "policy v" + std::to_string(s.policy_version), report.env_steps,
                 report.summary.avg_object_distance, report.summary.avg_distance, report.summary.success_rate);
  };

  status(rl::NodePhase::kStarting, "", true);
  while (!stop) {
    poll_updates();
    const bool training = s.have_weights && s.have_graph;

    if (evaluator && training) {
      if (!s.passive_evaluated) {
        evaluate(true);
        s.passive_evaluated = true;
      }
      if (s.learner && s.learner->training_env_steps >= s.next_eval_steps) {
        while (s.next_eval_steps <= s.learner->training_env_steps) s.next_eval_steps += c.actors.eval_every_env_steps;
        evaluate(false);
      }
    }
    if (budget_done()) {
      // the learner has all the data it wants: a last evaluation with the final weights
      if (evaluator && training && !stop) {
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        poll_updates();
        if (s.policy_version != s.evaluated_version) evaluate(false);
      }
      status(rl::NodePhase::kStopping, "budget done", true);
      return 0;
    }
    if (stop) break;

    // the graph service needs graph.episodes random episodes from all actors together: beyond
    // this actor's share (with a margin) it slows down to one episode a second until the
    // graph arrives, leaving the CPU to the GNN and the replay to useful data (it does not
    // stop: episodes sent before the service was listening are lost, and it may need more)
    const uint64_t explore_share = static_cast<uint64_t>(
        std::ceil(1.2 * c.graph.episodes / std::max(1, c.actors.count)));
    if (!training && !s.have_graph && counters_.episodes >= explore_share) {
      status(rl::NodePhase::kWaiting, "waiting for the graph (exploration share done)", false);
      const auto until = Clock::now() + std::chrono::seconds(1);
      while (!stop && Clock::now() < until && !s.have_graph) {
        if (auto p = link_->PollLearner(std::chrono::milliseconds(100))) s.learner = p;
        poll_updates();
      }
      if (stop || s.have_graph) continue;
    }

    std::optional<rl::Episode> episode;
    const uint64_t seed = c.run.seed * 1000003ull + actor_id_ * 100000007ull + next_episode_id_ + 7;
    if (!training) {
      status(rl::NodePhase::kExploring, s.have_graph ? "waiting for weights" : "waiting for the graph", false);
      episode = RunExploreEpisode(*s.env, c.actors.explore_episode_steps, seed, s.rng);
    } else {
      // rate limit: do not run more than the error buffer ahead of the learner. A learner
      // that is refilling its replay (a fresh start or a restart) cannot update: never wait
      // for it then, and count from the moment it can again.
      const double ratio = c.learner.updates_per_step;
      if (s.learner && (!s.baseline || s.learner->replay_size < c.learner.warmup_steps ||
                        s.learner->updates < s.baseline->updates))
        s.baseline = s.learner;
      while (!stop && ratio > 0 && s.learner && s.baseline) {
        if (s.learner->replay_size < c.learner.warmup_steps || s.learner->updates < s.baseline->updates) {
          s.baseline = s.learner;
          break;
        }
        const double inserted = static_cast<double>(s.learner->transitions_inserted - s.baseline->transitions_inserted);
        const double updates = static_cast<double>(s.learner->updates - s.baseline->updates);
        if (ratio * inserted - updates <= c.learner.rate_error_buffer + ratio * train.steps || budget_done()) break;
        ++counters_.waits;
        status(rl::NodePhase::kWaiting, "waiting for the learner", false);
        if (auto p = link_->PollLearner(std::chrono::milliseconds(200))) s.learner = p;
      }
      if (stop) break;
      status(rl::NodePhase::kTraining, "", false);
      episode = RunTrainEpisode(*s.env, *s.policy, s.structure, train, seed, s.rng);
    }
    if (!episode) {
      ++counters_.unstable_episodes;
      spdlog::warn("episode {} became physically unstable: dropped", next_episode_id_);
      ++next_episode_id_;
      continue;
    }
    episode->actor_id = actor_id_;
    episode->episode_id = next_episode_id_++;
    episode->policy_version = training ? s.policy_version : 0;
    episode->graph_version = s.graph_version;
    if (!link_->PublishEpisode(*episode)) break;
    counters_.env_steps += episode->num_steps;
    ++counters_.episodes;
  }
  status(rl::NodePhase::kStopping, "stopped", true);
  return 0;
}

}  // namespace srics::actor
