// The actors' side of the rate limiter against the real learner (issue 15): the stall where an
// actor waited for the learner for ever while the learner sat at its own rate limit, played
// deterministically by delivering the learner's stats to the actor only when a status period
// would have passed; and the learner's own backlog (LearnerStats.update_backlog) deciding.

#include <gtest/gtest.h>

#include "actor/actor_loop.h"
#include "common/links/in_memory_bus.h"
#include "common/rl/ground_truth.h"
#include "learner/learner_loop.h"

namespace srics::actor {
namespace {

config::Config SmallConfig() {
  return config::LoadConfig(
      std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml",
      {"actors.count=1", "actors.evaluators=0", "learner.warmup_steps=100", "learner.updates_per_step=1",
       "learner.rate_error_buffer=2", "learner.publish_every_updates=1000", "run.total_env_steps=100000",
       "agent.network.embed_dim=16", "agent.network.heads=2", "agent.network.policy_hidden=[16]",
       "agent.network.q_hidden=[16]", "agent.sac.batch_size=16"});
}

rl::GraphUpdate GroundTruth(const config::Config& config) {
  rl::GraphUpdate g;
  g.version = 1;
  g.graph = rl::GroundTruthGraph(config.env);
  g.structure = rl::ComputeSubgoalStructure(g.graph);
  return g;
}

// The actor's link with the learner's stats held back until Deliver(): what DDS does between
// two LearnerStats samples (one per status period) while the actor goes on inserting.
class StatsGate : public links::ActorLink {
 public:
  explicit StatsGate(std::unique_ptr<links::ActorLink> inner) : inner_(std::move(inner)) {}
  void Deliver() {
    if (auto p = inner_->PollLearner(std::chrono::milliseconds(0))) delivered_ = p;
  }
  std::optional<rl::WeightsUpdate> PollWeights(uint64_t newer_than) override { return inner_->PollWeights(newer_than); }
  std::optional<rl::GraphUpdate> PollGraph() override { return inner_->PollGraph(); }
  std::optional<rl::LearnerProgress> PollLearner(std::chrono::milliseconds) override { return delivered_; }
  bool PublishEpisode(const rl::Episode& episode) override { return inner_->PublishEpisode(episode); }
  void PublishEval(const rl::EvalReport& report) override { inner_->PublishEval(report); }
  void PublishStatus(const rl::NodeReport& report) override { inner_->PublishStatus(report); }

 private:
  std::unique_ptr<links::ActorLink> inner_;
  std::optional<rl::LearnerProgress> delivered_;
};

void StepUntilIdle(learner::LearnerLoop& loop) {
  for (int k = 0; k < 1000 && loop.Step() == learner::StepResult::kWorked; ++k) {
  }
}

TEST(ActorRateLimitTest, StatsFromBeforeTheWarmUpEndedDoNotStallTheRun) {
  const config::Config config = SmallConfig();
  links::InMemoryBus bus;
  bus.PublishGraph(GroundTruth(config));  // a fast graph: training starts before the warm-up ends
  StatsGate gate(bus.ActorEnd(0));
  auto learner_link = bus.LearnerEnd();
  learner::LearnerLoopOptions learner_options = learner::LearnerLoopOptionsFor(config, rl::RunShapeFor(config), "");
  learner_options.report_period_s = 0;  // it reports every step; the gate decides what the actor sees
  learner_options.final_weights_grace = std::chrono::milliseconds(0);
  learner::LearnerLoop learner(learner_options, learner_link.get());
  ActorLoop actor(ActorOptionsFor(config, rl::RunShapeFor(config), 0), &gate);

  StepUntilIdle(learner);  // first weights and stats
  gate.Deliver();
  for (int i = 0; i < 2; ++i) ASSERT_EQ(actor.Step(), StepResult::kWorked);  // 40 transitions
  StepUntilIdle(learner);
  gate.Deliver();  // the last stats the actor sees before the warm-up (100) ends: 40 inserted
  for (int i = 0; i < 5; ++i) ASSERT_EQ(actor.Step(), StepResult::kWorked);  // 100 more before the next stats
  StepUntilIdle(learner);
  // the learner's limiter: 40 updates for the 40 transitions past the warm-up, plus the buffer
  ASSERT_EQ(learner.learner().counters().transitions_inserted, 140u);
  ASSERT_EQ(learner.learner().counters().updates, 42u);
  ASSERT_FALSE(learner.learner().CanUpdate()) << "the learner is at its own limit: it needs data";
  // what it reports: 40 updates owed, 42 done
  EXPECT_DOUBLE_EQ(learner.learner().UpdateBacklog(), -2.0);

  // from here stats reach the actor every round, as the distributed run steps them
  for (int round = 0; round < 10; ++round) {
    gate.Deliver();
    actor.Step();
    StepUntilIdle(learner);
  }
  // counted from the stats of before the warm-up's end, the actor owed 100 - 42 updates and
  // waited for ever; counted from the first stats past it, it never has to wait
  EXPECT_EQ(actor.counters().waits, 0u);
  EXPECT_EQ(learner.learner().counters().transitions_inserted, 140u + 10 * 20);
  EXPECT_EQ(learner.learner().counters().updates, 42u + 10 * 20);
}

// Stats handed to an actor by hand (the learner itself is not needed).
class HandFedActor : public ::testing::Test {
 protected:
  HandFedActor() : config_(SmallConfig()), link_(bus_.ActorEnd(0)), learner_(bus_.LearnerEnd()) {
    bus_.PublishGraph(GroundTruth(config_));
    options_ = ActorOptionsFor(config_, rl::RunShapeFor(config_), 0);
    options_.status_period_s = 0;  // the valve then counts waits only
    actor_ = std::make_unique<ActorLoop>(options_, link_.get());
    // weights of the actor's architecture
    nn::Rng rng(5);
    rl::PolicyNetwork<float> policy("policy", options_.policy, rng);
    learner_->PublishWeights({1, 0, rl::PolicySignature(policy), nn::Flatten(policy.Parameters())});
  }
  void Stats(uint64_t inserted, uint64_t updates, double backlog) {
    rl::LearnerReport r;
    r.transitions_inserted = r.replay_size = inserted;
    r.updates = updates;
    r.update_backlog = backlog;
    r.budget_env_steps = 100000;
    learner_->PublishStats(r);
  }

  config::Config config_;
  links::InMemoryBus bus_;
  std::unique_ptr<links::ActorLink> link_;
  std::unique_ptr<links::LearnerLink> learner_;
  ActorOptions options_;
  std::unique_ptr<ActorLoop> actor_;
};

TEST_F(HandFedActor, TheActorHoldsBackWhileTheLearnersBacklogIsAboveTheBuffer) {
  Stats(1000, 900, 0);
  ASSERT_EQ(actor_->Step(), StepResult::kWorked);
  // 100 transitions in and 5 updates: 95 owed; the learner works it off, slowly
  for (uint64_t u = 905; u < 915; ++u) {
    Stats(1100, u, 100.0 - static_cast<double>(u - 900));
    EXPECT_EQ(actor_->Step(), StepResult::kIdle) << "updates " << u;
  }
  EXPECT_EQ(actor_->counters().waits, 10u);
  Stats(1100, 998, 2);  // caught up to the buffer of 2
  EXPECT_EQ(actor_->Step(), StepResult::kWorked);
}

// Whatever the counters, only the learner's own backlog decides: data its limiter does not
// count (the warm-up's, or what came while it waited for the graph) never holds actors back.
TEST_F(HandFedActor, OnlyTheLearnersOwnBacklogDecides) {
  Stats(1000, 0, 0);  // 1000 transitions and no update: all of them uncounted
  EXPECT_EQ(actor_->Step(), StepResult::kWorked);
  Stats(5000, 100, 1.5);
  EXPECT_EQ(actor_->Step(), StepResult::kWorked);
  Stats(5000, 100, 2.5);
  EXPECT_EQ(actor_->Step(), StepResult::kIdle);
  Stats(5000, 100, 0);  // a learner restarted from its checkpoint, say: counting afresh
  EXPECT_EQ(actor_->Step(), StepResult::kWorked);
}

TEST(ActorOptionsTest, AnEvaluatorWithoutAnEvaluationPeriodIsRefused) {
  links::InMemoryBus bus;
  auto link = bus.ActorEnd(0);
  config::Config config = SmallConfig();
  config.actors.evaluators = 1;
  ActorOptions options = ActorOptionsFor(config, rl::RunShapeFor(config), 0);
  options.eval_every_env_steps = 0;
  EXPECT_THROW(ActorLoop(options, link.get()), std::invalid_argument);
}

}  // namespace
}  // namespace srics::actor
