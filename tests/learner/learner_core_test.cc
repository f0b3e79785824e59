#include "learner/learner.h"

#include <gtest/gtest.h>


#include "tests/learner/learner_testing.h"

namespace srics::learner {
namespace {

using testing::MakeEpisode;
using testing::ResidentKb;
using testing::SmallRun;

TEST(LearnerCoreTest, GraphMethodsWaitForTheGraphWithoutPilingUpUpdates) {
  Learner learner(LearnerOptionsFor(SmallRun(config::Method::kSrics)));
  for (int i = 0; i < 50; ++i) ASSERT_EQ(learner.Ingest(MakeEpisode(3, 20, i, -1)), "");
  EXPECT_EQ(learner.counters().transitions_inserted, 1000u);
  EXPECT_FALSE(learner.CanUpdate()) << "no updates before the graph";
  learner.SetGraph(rl::ComputeSubgoalStructure(rl::InteractionGraph::Star(3)));
  // only the error buffer, not 0.5 * (1000 - 100) = 450 updates of allowance
  EXPECT_EQ(learner.UpdatesAllowed(), 4u);
  while (learner.CanUpdate()) learner.Update();
  EXPECT_EQ(learner.counters().updates, 4u);
  ASSERT_EQ(learner.Ingest(MakeEpisode(3, 20, 99, 1)), "");
  EXPECT_EQ(learner.UpdatesAllowed(), 10u);  // 20 transitions at 0.5 per step
}

TEST(LearnerCoreTest, DistanceMethodsStartAfterWarmup) {
  Learner learner(LearnerOptionsFor(SmallRun(config::Method::kSmorl)));
  for (int i = 0; i < 4; ++i) learner.Ingest(MakeEpisode(3, 20, i, 1));
  EXPECT_FALSE(learner.CanUpdate());  // 80 < warm-up of 100
  learner.Ingest(MakeEpisode(3, 20, 5, 1));
  EXPECT_TRUE(learner.CanUpdate());
  EXPECT_EQ(learner.UpdatesAllowed(), 4u);
}

TEST(LearnerCoreTest, RejectsEpisodesThatDoNotFitAndCountsThem) {
  Learner learner(LearnerOptionsFor(SmallRun(config::Method::kSrics)));
  rl::Episode wrong_layout = MakeEpisode(4, 20, 1, 1);  // 4 entities: this run has 3
  EXPECT_NE(learner.Ingest(wrong_layout).find("num_entities 4 outside [3, 3]"), std::string::npos);
  rl::Episode nan = MakeEpisode(3, 20, 2, 1);
  nan.states[7] = std::nanf("");
  EXPECT_NE(learner.Ingest(nan).find("states[7]"), std::string::npos);
  rl::Episode short_actions = MakeEpisode(3, 20, 3, 1);
  short_actions.actions.pop_back();
  EXPECT_NE(learner.Ingest(short_actions).find("actions has 39 values, expected 40"), std::string::npos);
  EXPECT_EQ(learner.episodes_rejected(), 3u);
  EXPECT_EQ(learner.replay().transitions(), 0u);
  EXPECT_EQ(learner.Ingest(MakeEpisode(3, 20, 4, 1)), "");
}

TEST(LearnerCoreTest, RestartFromCheckpointKeepsCountersAndRefillsBeforeUpdating) {
  const std::string path = ::testing::TempDir() + "/learner_core.srics";
  config::Config config = SmallRun(config::Method::kSmorl);
  Learner first(LearnerOptionsFor(config));
  for (int i = 0; i < 20; ++i) first.Ingest(MakeEpisode(3, 20, i, 1));
  while (first.CanUpdate()) first.Update();
  first.TakePolicyWeights();
  first.SaveCheckpoint(path);

  Learner second(LearnerOptionsFor(config));
  second.LoadCheckpoint(path);
  EXPECT_EQ(second.counters(), first.counters());
  EXPECT_EQ(second.agent().PolicyWeights(), first.agent().PolicyWeights());
  EXPECT_FALSE(second.CanUpdate()) << "empty replay after a restart";
  for (int i = 0; i < 5; ++i) second.Ingest(MakeEpisode(3, 20, 100 + i, 1));
  // the episode that completed the refill pays for 10 updates, plus the buffer of 4: not the
  // 0.5 * (500 - 100) + 4 - 154 = 50 that a limiter counting from zero would allow
  EXPECT_EQ(second.UpdatesAllowed(), 14u) << "no burst of updates after the refill";
  // weight versions keep increasing across the restart
  second.TakePolicyWeights();
  EXPECT_EQ(second.counters().policy_version, first.counters().policy_version + 1);
}

}  // namespace
}  // namespace srics::learner

namespace srics::learner {
namespace {

TEST(LearnerMemoryTest, FullReplayOf250kTransitionsAndPaperBatchStayUnder1GB) {
  // Rearrange 4 (5 entities), paper networks and batch 2048, a full 250k-transition replay
  config::Config c;
  c.env.num_pucks = 4;
  c.run.method = config::Method::kSrics;
  Learner learner(LearnerOptionsFor(c));
  learner.SetGraph(rl::ComputeSubgoalStructure(rl::InteractionGraph::Star(5)));
  for (int i = 0; i < 12600; ++i) ASSERT_EQ(learner.Ingest(testing::MakeEpisode(5, 20, i, i % 5)), "");
  EXPECT_EQ(learner.replay().transitions(), 250000u);
  ASSERT_TRUE(learner.CanUpdate());
  learner.Update();  // sizes every buffer of a batch-2048 update
  const double mb = ResidentKb() / 1024.0;
  RecordProperty("learner_rss_mb", std::to_string(mb));
  std::printf("learner with a full replay after a batch-2048 update: %.0f MB resident\n", mb);
  EXPECT_LT(mb, 1024);
}

}  // namespace
}  // namespace srics::learner
