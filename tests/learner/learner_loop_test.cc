// LearnerLoop driven step by step through the in-memory bus with real networks: first weights
// at once, the update-to-data ratio kept, a malformed episode refused and counted, a graph
// of the wrong size ignored, the end of the budget published.

#include "learner/learner_loop.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "common/links/in_memory_bus.h"
#include "tests/learner/learner_testing.h"

namespace srics::learner {
namespace {

class StatsObserver : public links::BusObserver {
 public:
  void OnLearnerStats(const rl::LearnerReport& report) override {
    last = report;
    ++reports;
  }
  rl::LearnerReport last;
  int reports = 0;
};

// SmallRun's sizes, a 400-step budget and weights every 10 updates.
LearnerLoopOptions SmallOptions() {
  config::Config c = testing::SmallRun(config::Method::kSrics);
  c.run.total_env_steps = 400;
  c.learner.publish_every_updates = 10;
  LearnerLoopOptions o = LearnerLoopOptionsFor(c, rl::RunShapeFor(c), "");
  o.report_period_s = 0;
  o.final_weights_grace = std::chrono::milliseconds(0);
  return o;
}

rl::GraphUpdate Star(int n, uint64_t version) {
  rl::GraphUpdate g;
  g.version = version;
  g.graph = rl::InteractionGraph::Star(n);
  g.structure = rl::ComputeSubgoalStructure(g.graph);
  return g;
}

TEST(LearnerLoopTest, KeepsTheRatioCountsRejectsAndEndsWithTheBudget) {
  StatsObserver observer;
  links::InMemoryBus bus(&observer);
  auto link = bus.LearnerEnd();
  auto actor = bus.ActorEnd(0);
  LearnerLoop loop(SmallOptions(), link.get());

  // the first step publishes weights at once: actors need them to start training
  EXPECT_EQ(loop.Step(), StepResult::kIdle);
  auto weights = actor->PollWeights(0);
  ASSERT_TRUE(weights.has_value());
  EXPECT_EQ(weights->version, 1u);
  EXPECT_FALSE(weights->parameters.empty());

  // a graph of another size is ignored; the right one is taken
  bus.PublishGraph(Star(4, 1));
  loop.Step();
  EXPECT_EQ(loop.graphs_rejected(), 1u);
  EXPECT_EQ(loop.graph_version(), 0u);
  bus.PublishGraph(Star(3, 2));
  loop.Step();
  EXPECT_EQ(loop.graph_version(), 2u);

  // a malformed episode (an action outside [-1, 1]) is refused, counted, and changes nothing
  rl::Episode bad = testing::MakeEpisode(3, 20, 1);
  bad.actions[3] = 5.0f;
  ASSERT_TRUE(actor->PublishEpisode(bad));
  loop.Step();
  EXPECT_EQ(loop.learner().episodes_rejected(), 1u);
  EXPECT_EQ(loop.learner().counters().transitions_inserted, 0u);
  EXPECT_EQ(observer.last.episodes_rejected, 1u);

  // 10 episodes of 20 steps: after the warm-up of 100 transitions, updates follow
  // 0.5 * (inserted - 100) within the error buffer of 4
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(actor->PublishEpisode(testing::MakeEpisode(3, 20, 100 + i)));
    for (int k = 0; k < 20 && loop.Step() != StepResult::kIdle; ++k) {
    }
    const auto& c = loop.learner().counters();
    const double target = c.transitions_inserted < 100 ? 0.0 : 0.5 * (c.transitions_inserted - 100.0);
    if (c.transitions_inserted < 100) {
      EXPECT_EQ(c.updates, 0u) << "no update during the warm-up";
      continue;
    }
    EXPECT_LE(static_cast<double>(c.updates), target + 4) << "after episode " << i;
    EXPECT_GE(static_cast<double>(c.updates), target + 4 - 1) << "after episode " << i << ": the learner lags";
  }
  EXPECT_EQ(loop.learner().counters().transitions_inserted, 200u);
  EXPECT_EQ(loop.learner().counters().updates, 54u);  // 0.5 * 100 + 4
  EXPECT_EQ(observer.last.updates, 54u);
  EXPECT_GT(actor->PollWeights(0)->version, 1u) << "weights are published every 10 updates";

  // the rest of the budget (400 env steps): the loop ends, the end is in the stats
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(actor->PublishEpisode(testing::MakeEpisode(3, 20, 200 + i)));
  // once the budget's data are in, the learner works off the updates it owes (the last 2 x 4
  // of them within its error buffer) while its stats hold the actors back: their episodes
  // would be dropped (in process they took the learner's time: 8-10 min at a 150k run's end)
  StepResult last = StepResult::kWorked;
  int held_back = 0;
  for (int k = 0; k < 1000 && last != StepResult::kDone; ++k) {
    last = loop.Step();
    if (last != StepResult::kDone && loop.learner().BudgetReached() && loop.learner().UpdateBacklog() <= 4) {
      EXPECT_GT(observer.last.update_backlog, 4.0) << "updates " << loop.learner().counters().updates;
      ++held_back;
    }
  }
  EXPECT_GT(held_back, 0);
  EXPECT_EQ(last, StepResult::kDone);
  EXPECT_TRUE(observer.last.progress().budget_done());
  EXPECT_EQ(loop.learner().counters().updates, 154u);
  EXPECT_TRUE(actor->PollLearner(std::chrono::milliseconds(0))->budget_done());
}

// updates_on_ratio_only (the two-thread in-process run): after each episode the learner has done
// exactly the updates the data pays for, none of the error buffer's, in one step however many
// they are; once the budget is in it works off the buffer as before and ends with the same count.
TEST(LearnerLoopTest, OnRatioOnlyKeepsTheRatioExactlyAndEndsAsBefore) {
  StatsObserver observer;
  links::InMemoryBus bus(&observer);
  auto link = bus.LearnerEnd();
  auto actor = bus.ActorEnd(0);
  LearnerLoopOptions options = SmallOptions();
  options.updates_on_ratio_only = true;
  options.max_updates_per_step = std::numeric_limits<int>::max();
  LearnerLoop loop(options, link.get());
  loop.Step();
  bus.PublishGraph(Star(3, 1));
  loop.Step();
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(actor->PublishEpisode(testing::MakeEpisode(3, 20, 100 + i)));
    loop.Step();  // one step does all of them
    const auto& c = loop.learner().counters();
    const double target = c.transitions_inserted < 100 ? 0.0 : 0.5 * (c.transitions_inserted - 100.0);
    EXPECT_EQ(static_cast<double>(c.updates), target) << "after episode " << i;
    EXPECT_LT(observer.last.update_backlog, 1.0) << "the actors are never held back";
  }
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(actor->PublishEpisode(testing::MakeEpisode(3, 20, 200 + i)));
  StepResult last = StepResult::kWorked;
  for (int k = 0; k < 1000 && last != StepResult::kDone; ++k) last = loop.Step();
  EXPECT_EQ(last, StepResult::kDone);
  EXPECT_EQ(loop.learner().counters().updates, 154u);  // as without: 0.5 * 300 + 4
}

// No episode is ingested twice: one delivered again (a replay by a foreign participant, a
// retransmission) is refused and counted under episode.duplicate; a refused malformed copy
// does not burn the id of the good episode that follows.
TEST(LearnerLoopTest, AnEpisodeDeliveredTwiceIsIngestedOnce) {
  links::InMemoryBus bus;
  auto link = bus.LearnerEnd();
  auto actor = bus.ActorEnd(0);
  LearnerLoop loop(SmallOptions(), link.get());
  loop.Step();
  const rl::Episode good = testing::MakeEpisode(3, 20, 5);
  ASSERT_TRUE(actor->PublishEpisode(good));
  ASSERT_TRUE(actor->PublishEpisode(good));
  loop.Step();
  EXPECT_EQ(loop.learner().counters().episodes_accepted, 1u);
  EXPECT_EQ(loop.learner().counters().transitions_inserted, 20u);
  EXPECT_EQ(loop.duplicates_refused(), 1u);

  rl::Episode bad = testing::MakeEpisode(3, 20, 6);
  bad.actions[3] = 5.0f;
  ASSERT_TRUE(actor->PublishEpisode(bad));
  ASSERT_TRUE(actor->PublishEpisode(testing::MakeEpisode(3, 20, 6)));
  ASSERT_TRUE(actor->PublishEpisode(good));
  loop.Step();
  EXPECT_EQ(loop.learner().episodes_rejected(), 1u);
  EXPECT_EQ(loop.learner().counters().episodes_accepted, 2u);
  EXPECT_EQ(loop.duplicates_refused(), 2u);
}

// A learner whose networks went non-finite would skip every update and train on unchanged,
// its stats frozen (a HAC run did, for 45k updates). A few skipped updates in a row are
// survived; learner.max_skipped_updates_in_a_row of them end the run with an error naming the
// stage.
TEST(LearnerLoopTest, EndlesslySkippedUpdatesEndTheRunNamingTheStage) {
  links::InMemoryBus bus;
  auto link = bus.LearnerEnd();
  auto actor = bus.ActorEnd(0);
  LearnerLoopOptions options = SmallOptions();
  options.learner.learner.max_skipped_updates_in_a_row = 20;
  LearnerLoop loop(options, link.get());
  loop.Step();
  bus.PublishGraph(Star(3, 1));
  uint64_t episode_id = 1;
  // steps until `updates` more updates ran (episodes fed as the ratio asks)
  auto run_updates = [&](uint64_t updates) {
    const uint64_t target = loop.learner().counters().updates + updates;
    for (int k = 0; k < 2000 && loop.learner().counters().updates < target; ++k) {
      if (!loop.learner().CanUpdate()) ASSERT_TRUE(actor->PublishEpisode(testing::MakeEpisode(3, 20, episode_id++)));
      loop.Step();
    }
    ASSERT_GE(loop.learner().counters().updates, target);
  };
  run_updates(10);
  EXPECT_EQ(loop.learner().non_finite_updates(), 0u);

  // a NaN in the policy makes every Bellman target NaN: updates are skipped, the run goes on
  nn::Parameter<float>& weight = *loop.learner().agent().policy().Parameters().front();
  const float good = weight.value(0, 0);
  weight.value(0, 0) = std::numeric_limits<float>::quiet_NaN();
  run_updates(12);
  EXPECT_GE(loop.learner().non_finite_in_a_row(), 12u);
  EXPECT_LT(loop.learner().non_finite_in_a_row(), 20u);
  // a finite update ends the stretch
  weight.value(0, 0) = good;
  run_updates(3);
  EXPECT_EQ(loop.learner().non_finite_in_a_row(), 0u);
  const uint64_t skipped = loop.learner().non_finite_updates();
  EXPECT_GE(skipped, 12u);

  weight.value(0, 0) = std::numeric_limits<float>::quiet_NaN();
  try {
    run_updates(100);
    FAIL() << "the run went on after 20 skipped updates in a row";
  } catch (const LearningDivergedError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("the last 20 updates"), std::string::npos) << message;
    EXPECT_NE(message.find("critic targets"), std::string::npos) << message;
    EXPECT_NE(message.find("learner.max_skipped_updates_in_a_row"), std::string::npos) << message;
  }
  EXPECT_EQ(loop.learner().non_finite_updates(), skipped + 20);
}

}  // namespace
}  // namespace srics::learner
