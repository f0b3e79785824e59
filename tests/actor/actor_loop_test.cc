// ActorLoop driven step by step through the in-memory bus, with the real environment and
// real networks: what it publishes, when it adopts weights and graphs, what it refuses, when
// it holds back for the learner and when it ends.

#include "actor/actor_loop.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <set>

#include "actor/env/rearrange_env.h"
#include "common/config/config_error.h"
#include "common/links/in_memory_bus.h"
#include "common/nn/serialize.h"
#include "common/rl/agent_shape.h"
#include "common/rl/ground_truth.h"
#include "common/rl/seeds.h"

namespace srics::actor {
namespace {

config::Config SmallConfig() {
  return config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml",
                            {"graph.episodes=4", "graph.held_out_fraction=0.25", "actors.count=2",
                             "actors.evaluators=1", "actors.eval_episodes=2", "actors.eval_every_env_steps=100",
                             "learner.warmup_steps=40", "learner.updates_per_step=1", "learner.rate_error_buffer=10"});
}

// Weights of a policy with the actor's own architecture, as the learner would publish them.
rl::WeightsUpdate WeightsFor(const ActorOptions& options, uint64_t version, uint64_t seed) {
  nn::Rng rng(seed);
  rl::PolicyNetwork<float> policy("policy", options.policy, rng);
  return {version, version * 10, rl::PolicySignature(policy), nn::Flatten(policy.Parameters())};
}

rl::GraphUpdate GroundTruth(const config::Config& config, uint64_t version) {
  rl::GraphUpdate g;
  g.version = version;
  g.graph = rl::GroundTruthGraph(config.env);
  g.structure = rl::ComputeSubgoalStructure(g.graph);
  return g;
}

std::vector<rl::Episode> Drain(links::LearnerLink& learner) {
  std::vector<rl::Episode> out;
  learner.TakeEpisodes(&out, 1000, std::chrono::milliseconds(0));
  return out;
}

class CountingObserver : public links::BusObserver {
 public:
  void OnEval(const rl::EvalReport& report) override { evals.push_back(report); }
  std::vector<rl::EvalReport> evals;
};

// Actor 0 (an evaluator) on a bus that records the evaluations, with the ground-truth graph
// (version 1) and weights of version 1 published from the start.
struct EvaluatorOnBus {
  EvaluatorOnBus()
      : config(SmallConfig()),
        bus(&observer),
        link(bus.ActorEnd(0)),
        learner(bus.LearnerEnd()),
        options(ActorOptionsFor(config, rl::RunShapeFor(config), 0)),
        actor(options, link.get()) {
    bus.PublishGraph(GroundTruth(config, 1));
    learner->PublishWeights(WeightsFor(options, 1, 21));
  }
  const config::Config config;
  CountingObserver observer;
  links::InMemoryBus bus;
  std::unique_ptr<links::ActorLink> link;
  std::unique_ptr<links::LearnerLink> learner;
  const ActorOptions options;
  ActorLoop actor;
};

// The stats of a learner past its warm-up: 100 transitions in, 60 updates done.
rl::LearnerReport PastWarmUp() {
  rl::LearnerReport stats;
  stats.replay_size = stats.transitions_inserted = 100;
  stats.updates = 60;
  return stats;
}

TEST(ActorLoopTest, ExploresUntilGraphAndWeightsThenTrainsWithTheNewestWeights) {
  const config::Config config = SmallConfig();
  links::InMemoryBus bus;
  auto link = bus.ActorEnd(1);
  auto learner = bus.LearnerEnd();
  ActorOptions options = ActorOptionsFor(config, rl::RunShapeFor(config), 1);
  options.explore_while_waiting_s = 0;
  ActorLoop actor(options, link.get());

  // no graph and no weights: whole random episodes of explore_episode_steps
  ASSERT_EQ(actor.Step(), StepResult::kWorked);
  auto episodes = Drain(*learner);
  ASSERT_EQ(episodes.size(), 1u);
  const rl::Episode& explore = episodes[0];
  EXPECT_EQ(explore.mode, rl::EpisodeMode::kExplore);
  EXPECT_EQ(explore.num_steps, config.actors.explore_episode_steps);
  EXPECT_EQ(explore.layout.num_entities, 2);
  EXPECT_EQ(explore.states.size(), static_cast<size_t>(explore.num_steps + 1) * explore.layout.state_size());
  EXPECT_EQ(explore.actor_id, 1u);
  EXPECT_EQ(explore.episode_id, 0u);
  EXPECT_EQ(explore.policy_version, 0u);
  EXPECT_EQ(rl::ValidateEpisode(explore, rl::EpisodeLimitsFor(config.env)), "");

  // its share of the graph's data is ceil(1.2 * 4 / 2) = 3 episodes; then it waits
  EXPECT_EQ(actor.Step(), StepResult::kWorked);
  EXPECT_EQ(actor.Step(), StepResult::kWorked);
  EXPECT_EQ(actor.Step(), StepResult::kIdle);
  EXPECT_EQ(Drain(*learner).size(), 2u);

  // graph and weights: training episodes on subgoals, with the weights' version
  bus.PublishGraph(GroundTruth(config, 1));
  learner->PublishWeights(WeightsFor(options, 1, 11));
  ASSERT_EQ(actor.Step(), StepResult::kWorked);
  episodes = Drain(*learner);
  ASSERT_EQ(episodes.size(), 1u);
  EXPECT_EQ(episodes[0].mode, rl::EpisodeMode::kTrain);
  EXPECT_EQ(episodes[0].num_steps, config.actors.train_episode_steps);
  EXPECT_EQ(episodes[0].policy_version, 1u);
  EXPECT_EQ(episodes[0].graph_version, 1u);
  EXPECT_GE(episodes[0].subgoal_entity, 0);
  EXPECT_EQ(episodes[0].goal.size(), 2u);
  EXPECT_EQ(episodes[0].episode_id, 3u);

  // new weights are taken between episodes
  learner->PublishWeights(WeightsFor(options, 2, 12));
  ASSERT_EQ(actor.Step(), StepResult::kWorked);
  episodes = Drain(*learner);
  ASSERT_EQ(episodes.size(), 1u);
  EXPECT_EQ(episodes[0].policy_version, 2u);
  EXPECT_EQ(actor.counters().weights_rejected, 0u);

  // weights of another architecture and a graph of another size are refused and counted
  rl::WeightsUpdate wrong = WeightsFor(options, 3, 13);
  wrong.parameters.pop_back();
  learner->PublishWeights(wrong);
  rl::GraphUpdate bigger;
  bigger.version = 2;
  bigger.graph = rl::InteractionGraph::Star(3);
  bigger.structure = rl::ComputeSubgoalStructure(bigger.graph);
  bus.PublishGraph(bigger);
  ASSERT_EQ(actor.Step(), StepResult::kWorked);
  EXPECT_EQ(actor.counters().weights_rejected, 1u);
  EXPECT_EQ(actor.counters().graphs_rejected, 1u);
  episodes = Drain(*learner);
  ASSERT_EQ(episodes.size(), 1u);
  EXPECT_EQ(episodes[0].policy_version, 2u);
  EXPECT_EQ(episodes[0].graph_version, 1u);
  EXPECT_EQ(actor.counters().episodes, 6u);
  EXPECT_EQ(actor.counters().env_steps, 3u * 50 + 3u * 20);
}

// The first and the last row of an episode's states.
std::vector<float> StateRow(const rl::Episode& e, int t) {
  const size_t size = e.layout.state_size();
  return std::vector<float>(e.states.begin() + t * size, e.states.begin() + (t + 1) * size);
}

// actors.train_chain_episodes: with 3, training episodes come in chains of three, the second
// and third starting exactly where the one before left the table (objects where it pushed
// them), the fourth from a reset; with the default 1 every episode starts from a reset.
TEST(ActorLoopTest, ChainedTrainingEpisodesStartWhereTheLastLeftTheTable) {
  for (const int chain : {1, 3}) {
    SCOPED_TRACE("train_chain_episodes " + std::to_string(chain));
    config::Config config =
        config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml",
                           {"graph.episodes=4", "graph.held_out_fraction=0.25", "actors.count=2", "actors.evaluators=1",
                            "learner.warmup_steps=100000", "actors.train_chain_episodes=" + std::to_string(chain)});
    EXPECT_EQ(config.actors.train_chain_episodes, chain);
    links::InMemoryBus bus;
    auto link = bus.ActorEnd(1);
    auto learner = bus.LearnerEnd();
    ActorOptions options = ActorOptionsFor(config, rl::RunShapeFor(config), 1);
    options.explore_while_waiting_s = 0;
    EXPECT_EQ(options.train.chain_episodes, chain);
    ActorLoop actor(options, link.get());
    bus.PublishGraph(GroundTruth(config, 1));
    learner->PublishWeights(WeightsFor(options, 1, 11));
    std::vector<rl::Episode> training;
    for (int k = 0; k < 40 && training.size() < 7; ++k) {
      actor.Step();
      for (rl::Episode& e : Drain(*learner))
        if (e.mode == rl::EpisodeMode::kTrain) training.push_back(std::move(e));
    }
    ASSERT_EQ(training.size(), 7u);
    for (size_t i = 1; i < training.size(); ++i) {
      const bool continues = StateRow(training[i], 0) == StateRow(training[i - 1], training[i - 1].num_steps);
      EXPECT_EQ(continues, chain > 1 && i % 3 != 0) << "episode " << i;
    }
  }
  // the key is checked
  EXPECT_THROW(config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml",
                                  {"actors.train_chain_episodes=0"}),
               config::ConfigError);
}

// A refined graph (graph.refine_after_publish) arrives as a new version while the actor trains:
// every episode runs on one structure, and the next one on the newest.
TEST(ActorLoopTest, ANewGraphVersionChangesTheSubgoalsFromTheNextEpisode) {
  const config::Config config = SmallConfig();
  links::InMemoryBus bus;
  auto link = bus.ActorEnd(1);
  auto learner = bus.LearnerEnd();
  ActorLoop actor(ActorOptionsFor(config, rl::RunShapeFor(config), 1), link.get());
  bus.PublishGraph(GroundTruth(config, 1));  // the arm drives the puck: both have subgoals
  learner->PublishWeights(WeightsFor(ActorOptionsFor(config, rl::RunShapeFor(config), 1), 1, 31));
  auto subgoals_of_next_episodes = [&](int count, uint64_t version) {
    std::set<int> entities;
    for (int i = 0; i < count; ++i) {
      EXPECT_EQ(actor.Step(), StepResult::kWorked);
      for (const rl::Episode& e : Drain(*learner)) {
        EXPECT_EQ(e.mode, rl::EpisodeMode::kTrain);
        EXPECT_EQ(e.graph_version, version);
        entities.insert(e.subgoal_entity);
      }
    }
    return entities;
  };
  EXPECT_EQ(subgoals_of_next_episodes(12, 1), (std::set<int>{0, 1}));
  // version 2: nothing acts on the puck any more, so it has no subgoal
  rl::GraphUpdate v2 = GroundTruth(config, 2);
  std::fill(v2.graph.adjacency.begin(), v2.graph.adjacency.end(), 0);
  v2.structure = rl::ComputeSubgoalStructure(v2.graph);
  ASSERT_FALSE(v2.structure.has_subgoal(1));
  bus.PublishGraph(v2);
  EXPECT_EQ(subgoals_of_next_episodes(12, 2), (std::set<int>{0}));
  EXPECT_EQ(actor.graph_version(), 2u);
  EXPECT_EQ(actor.counters().graphs_rejected, 0u);
}

TEST(ActorLoopTest, HoldsBackWhenAheadOfTheLearnerAndEndsWithTheBudget) {
  EvaluatorOnBus evaluator;
  ASSERT_TRUE(evaluator.options.evaluator);

  // a learner past its warm-up, with nothing owed
  rl::LearnerReport stats = PastWarmUp();
  stats.budget_env_steps = 1000;
  evaluator.learner->PublishStats(stats);
  // an evaluator first evaluates the passive policy
  ASSERT_EQ(evaluator.actor.Step(), StepResult::kWorked);
  ASSERT_EQ(evaluator.observer.evals.size(), 1u);
  EXPECT_EQ(evaluator.observer.evals[0].policy_version, 0u);
  EXPECT_EQ(evaluator.observer.evals[0].summary.episodes, 2);
  ASSERT_EQ(evaluator.actor.Step(), StepResult::kWorked);  // a training episode
  // 20 more transitions in and no update: the learner owes 20 > error buffer (10): wait
  stats.transitions_inserted = 120;
  stats.update_backlog = 20;
  evaluator.learner->PublishStats(stats);
  EXPECT_EQ(evaluator.actor.Step(), StepResult::kIdle);
  EXPECT_EQ(evaluator.actor.counters().waits, 1u);
  // the learner catches up: go on
  stats.updates = 80;
  stats.update_backlog = 0;
  evaluator.learner->PublishStats(stats);
  EXPECT_EQ(evaluator.actor.Step(), StepResult::kWorked);

  // the evaluation schedule follows the learner's env steps (every 100)
  stats.training_env_steps = 150;
  stats.updates = 100;
  evaluator.learner->PublishStats(stats);
  ASSERT_EQ(evaluator.actor.Step(), StepResult::kWorked);
  ASSERT_EQ(evaluator.observer.evals.size(), 2u);
  EXPECT_EQ(evaluator.observer.evals[1].policy_version, 1u);
  EXPECT_EQ(evaluator.observer.evals[1].env_steps, 150u);

  // the budget is done: one more look for the final weights, a last evaluation, the end
  evaluator.learner->PublishWeights(WeightsFor(evaluator.options, 2, 22));
  stats.training_env_steps = 1000;
  evaluator.learner->PublishStats(stats);
  EXPECT_EQ(evaluator.actor.Step(), StepResult::kIdle);
  EXPECT_EQ(evaluator.actor.Step(), StepResult::kDone);
  ASSERT_EQ(evaluator.observer.evals.size(), 3u);
  EXPECT_EQ(evaluator.observer.evals[2].policy_version, 2u);
}

// Issue 15: the next evaluation was found by adding the interval until it passed the
// learner's step count: a count of 2^62 (one stray LearnerStats sample) kept an evaluating
// actor in that loop for good, and counters below the rate limiter's baseline wrapped around.
TEST(ActorLoopTest, HugeStepCountsNeitherHangTheScheduleNorWrapTheRateLimit) {
  EvaluatorOnBus evaluator;
  rl::LearnerReport stats = PastWarmUp();
  evaluator.learner->PublishStats(stats);
  ASSERT_EQ(evaluator.actor.Step(), StepResult::kWorked);  // the passive evaluation
  stats.training_env_steps = uint64_t{1} << 62;
  stats.transitions_inserted = (uint64_t{1} << 62) + 100;
  evaluator.learner->PublishStats(stats);
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(evaluator.actor.Step(), StepResult::kWorked);  // evaluates once, at once
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30.0);
  ASSERT_EQ(evaluator.observer.evals.size(), 2u);
  // a learner that starts again from fewer inserted transitions: counted afresh, no wait
  stats.training_env_steps = 0;
  stats.transitions_inserted = 50;
  stats.updates = 60;
  evaluator.learner->PublishStats(stats);
  EXPECT_EQ(evaluator.actor.Step(), StepResult::kWorked);
  EXPECT_EQ(evaluator.actor.counters().waits, 0u);
}

// Issue 15: a policy whose output is not finite made the environment throw, which ended the
// actor (and every actor, with the same weights). The episode is now dropped as unstable.
TEST(ActorLoopTest, NonFiniteActionsDropTheEpisodeInsteadOfThrowing) {
  const config::Config config = SmallConfig();
  auto env = env::MakeRearrangeEnv(config.env);
  const ActorOptions options = ActorOptionsFor(config, rl::RunShapeFor(config), 0);
  nn::Rng rng(1);
  rl::PolicyNetwork<float> policy("policy", options.policy, rng);
  std::vector<float> flat = nn::Flatten(policy.Parameters());
  std::fill(flat.begin(), flat.end(), std::numeric_limits<float>::quiet_NaN());
  nn::LoadFlat(policy.Parameters(), flat);
  const rl::CatalogueSubgoals subgoals{rl::GroundTruthGraph(config.env)};
  std::optional<rl::Episode> episode;
  EXPECT_NO_THROW(episode = RunTrainEpisode(*env, policy, subgoals, options.train, 1, rng));
  EXPECT_FALSE(episode.has_value());
  // the environment is usable for the next episode
  std::optional<rl::Episode> explore;
  EXPECT_NO_THROW(explore = RunExploreEpisode(*env, options.explore, 2, rng));
  EXPECT_TRUE(explore.has_value());
}

// graph.object_ties: joint on Relational Rearrange 4 (the tied pucks 2 <-> 3 in the campaign's
// two-way graph): the policy takes two goal tokens, a training episode of the pair carries
// both pucks' goals (4 floats, a valid episode), none is of puck 3 alone, and an evaluation
// attempts the pair as one subgoal, never puck 3 by itself.
class AttemptLog : public EvalEpisodeObserver {
 public:
  void OnState(const env::Environment&, int) override {}
  void OnAttempt(const Attempt& attempt) override { attempts.push_back(attempt); }
  std::vector<Attempt> attempts;
};

TEST(ActorLoopTest, JointTiesTrainAndEvaluateTheTiedPairAsOneSubgoal) {
  const std::string configs = std::string(SRICS_SOURCE_DIR) + "/deploy/configs/";
  const config::Config config = config::LoadConfig(
      configs + "relational-4.yaml",
      {"graph.object_ties=joint", "graph.file=" + configs + "campaign/graphs/relational-4-two-way.json"});
  const ActorOptions options = ActorOptionsFor(config, rl::RunShapeFor(config), 0);
  ASSERT_EQ(options.policy.goal_tokens, 2);
  auto env = env::MakeRearrangeEnv(config.env);
  nn::Rng rng(3);
  rl::PolicyNetwork<float> policy("policy", options.policy, rng);
  rl::InteractionGraph graph;
  graph.num_entities = 5;
  graph.adjacency.assign(25, 0);
  for (auto [a, b] : std::vector<std::pair<int, int>>{{0, 2}, {0, 3}, {0, 4}, {2, 3}, {3, 2}})
    graph.adjacency[a * 5 + b] = 1;
  const rl::CatalogueSubgoals subgoals{graph, true};
  std::set<int> entities;
  for (uint64_t seed = 1; seed <= 24; ++seed) {
    const std::optional<rl::Episode> e = RunTrainEpisode(*env, policy, subgoals, options.train, seed, rng);
    ASSERT_TRUE(e.has_value());
    EXPECT_EQ(rl::ValidateEpisode(*e, rl::EpisodeLimitsFor(config.env)), "");
    entities.insert(e->subgoal_entity);
    EXPECT_EQ(e->goal.size(), e->subgoal_entity == 2 ? 4u : 2u) << "subgoal " << e->subgoal_entity;
  }
  EXPECT_EQ(entities, (std::set<int>{0, 2, 4}));
  AttemptLog log;
  const std::optional<rl::EpisodeMetrics> metrics =
      RunEvaluationEpisode(*env, &policy, subgoals, options.eval, 7, nullptr, &log);
  ASSERT_TRUE(metrics.has_value());
  ASSERT_FALSE(log.attempts.empty());
  for (const auto& attempt : log.attempts) {
    EXPECT_NE(attempt.entity, 3);
    // the pair's partner is never among the "others" its own attempt disturbs, and the pair's
    // row holds the farther of its two pucks' distances
    if (attempt.entity == 2) {
      EXPECT_EQ(std::count(attempt.solved_others.begin(), attempt.solved_others.end(), 3), 0);
      EXPECT_EQ(attempt.distance_after, std::max(attempt.distances_after[2], attempt.distances_after[3]));
      EXPECT_EQ(attempt.distance_before, std::max(attempt.distances_before[2], attempt.distances_before[3]));
    }
  }
}

TEST(ActorLoopTest, SameSeedSameEpisodes) {
  const config::Config config = SmallConfig();
  std::vector<std::vector<float>> runs[2];
  for (auto& states : runs) {
    links::InMemoryBus bus;
    auto link = bus.ActorEnd(0);
    auto learner = bus.LearnerEnd();
    ActorLoop actor(ActorOptionsFor(config, rl::RunShapeFor(config), 0), link.get());
    for (int i = 0; i < 2; ++i) actor.Step();
    for (auto& e : Drain(*learner)) states.push_back(e.states);
  }
  ASSERT_EQ(runs[0].size(), 2u);
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_NE(runs[0][0], runs[0][1]);
}

}  // namespace
}  // namespace srics::actor
