#include "learner/learner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "common/nn/serialize.h"
#include "common/process/memory.h"

#include "tests/learner/learner_testing.h"

namespace srics::learner {
namespace {

using testing::MakeEpisode;
using testing::OptionsOf;
using testing::ResidentKb;
using testing::SmallRun;

TEST(LearnerCoreTest, GraphMethodsWaitForTheGraphWithoutPilingUpUpdates) {
  Learner learner(OptionsOf(SmallRun(config::Method::kSrics)));
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
  Learner learner(OptionsOf(SmallRun(config::Method::kSmorl)));
  for (int i = 0; i < 4; ++i) learner.Ingest(MakeEpisode(3, 20, i, 1));
  EXPECT_FALSE(learner.CanUpdate());  // 80 < warm-up of 100
  learner.Ingest(MakeEpisode(3, 20, 5, 1));
  EXPECT_TRUE(learner.CanUpdate());
  EXPECT_EQ(learner.UpdatesAllowed(), 4u);
}

TEST(LearnerCoreTest, RejectsEpisodesThatDoNotFitAndCountsThem) {
  Learner learner(OptionsOf(SmallRun(config::Method::kSrics)));
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

// A learner restarted from its checkpoint goes on as if uninterrupted: the same replay, the
// same counters and limiter state, and the next updates equal the original's bit for bit.
TEST(LearnerCoreTest, RestartFromCheckpointKeepsTheReplayAndGoesOnAsIfUninterrupted) {
  const std::string path = ::testing::TempDir() + "/learner_core.srics";
  config::Config config = SmallRun(config::Method::kSrics);
  config.learner.replay_capacity = 300;  // some episodes have left already
  Learner first(LearnerOptionsFor(config, rl::RunShapeFor(config)));
  for (int i = 0; i < 10; ++i) first.Ingest(MakeEpisode(3, 20, i, -1));  // explore, before the graph
  const auto graph = rl::ComputeSubgoalStructure(rl::InteractionGraph::Star(3));
  first.SetGraph(graph);
  for (int i = 10; i < 22; ++i) {
    first.Ingest(MakeEpisode(3, 20, i, i % 3));
    while (first.CanUpdate()) first.Update();
  }
  first.Ingest(MakeEpisode(3, 20, 40, 1));  // allowance left unused at the checkpoint
  first.TakePolicyWeights();
  first.SaveCheckpoint(path);

  Learner second(LearnerOptionsFor(config, rl::RunShapeFor(config)));
  second.LoadCheckpoint(path);
  second.SetGraph(graph);  // the graph service re-publishes its graph after a restart
  EXPECT_TRUE(second.replay_restored());
  EXPECT_EQ(second.counters(), first.counters());
  EXPECT_EQ(second.replay().contents(), first.replay().contents());
  EXPECT_EQ(second.replay().transitions(), 300u);
  EXPECT_EQ(second.replay().inserted_total(), first.replay().inserted_total());
  EXPECT_EQ(second.agent().PolicyWeights(), first.agent().PolicyWeights());
  ASSERT_GT(first.UpdatesAllowed(), 0u);
  EXPECT_EQ(second.UpdatesAllowed(), first.UpdatesAllowed()) << "the rate limiter's state is kept";
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(second.CanUpdate());
    const UpdateStats a = first.Update(), b = second.Update();
    EXPECT_EQ(a.q_loss, b.q_loss) << "update " << i;
    EXPECT_EQ(a.policy_loss, b.policy_loss) << "update " << i;
    EXPECT_EQ(a.mean_reward, b.mean_reward) << "update " << i;
  }
  first.Ingest(MakeEpisode(3, 20, 41, 2));
  second.Ingest(MakeEpisode(3, 20, 41, 2));
  EXPECT_EQ(second.UpdatesAllowed(), first.UpdatesAllowed());
  EXPECT_EQ(second.replay().contents(), first.replay().contents());
  // weight versions keep increasing across the restart
  second.TakePolicyWeights();
  EXPECT_EQ(second.counters().policy_version, first.counters().policy_version + 1);
}

// Ingests `episodes` episodes of 3 entities (seeds 0, 1, ...) and runs every update they allow.
void IngestAndUpdate(Learner& learner, int episodes) {
  for (int i = 0; i < episodes; ++i) learner.Ingest(MakeEpisode(3, 20, i, 1));
  while (learner.CanUpdate()) learner.Update();
}

// A truncated or corrupted checkpoint is a clear nn::CheckpointError and leaves the learner
// as it was.
TEST(LearnerCoreTest, ABrokenCheckpointIsRefusedWithAMessageAndChangesNothing) {
  const std::string path = ::testing::TempDir() + "/learner_core_broken.srics";
  config::Config config = SmallRun(config::Method::kSmorl);
  Learner first(LearnerOptionsFor(config, rl::RunShapeFor(config)));
  IngestAndUpdate(first, 12);
  first.SaveCheckpoint(path);
  std::string data;
  {
    std::ifstream in(path, std::ios::binary);
    data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto expect_refused = [&](const std::string& contents, const std::string& what) {
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(contents.data(), contents.size());
    Learner second(LearnerOptionsFor(config, rl::RunShapeFor(config)));
    second.Ingest(MakeEpisode(3, 20, 99, 1));
    try {
      second.LoadCheckpoint(path);
      ADD_FAILURE() << "no error, expected '" << what << "'";
    } catch (const nn::CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    EXPECT_EQ(second.replay().episodes(), 1u);
    EXPECT_EQ(second.counters().transitions_inserted, 20u);
  };
  for (size_t keep : {size_t{6}, size_t{100}, data.size() / 2, data.size() - 9, data.size() - 1})
    expect_refused(data.substr(0, keep), "truncated");
  std::string flipped = data;
  flipped[data.size() - 100] ^= 0x01;  // inside the replay
  expect_refused(flipped, "checksum mismatch (corrupted)");
  // a checkpoint of another environment: its replay does not fit this run
  config::Config other = config;
  other.env.num_pucks = 3;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(data.data(), data.size());
  Learner wider(LearnerOptionsFor(other, rl::RunShapeFor(other)));
  try {
    wider.LoadCheckpoint(path);
    ADD_FAILURE() << "a replay of 3 entities loaded into a run of 4";
  } catch (const nn::CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("replay episode 0: num_entities 3"), std::string::npos) << e.what();
  }
  EXPECT_EQ(wider.replay().episodes(), 0u);
}

// A checkpoint written before the replay was saved (agent sections only) still loads: networks
// and counters come back, the replay starts empty and the warm-up refills it without a burst.
TEST(LearnerCoreTest, ACheckpointWithoutReplayLoadsAndRefillsBeforeUpdating) {
  const std::string path = ::testing::TempDir() + "/learner_core_old.srics";
  config::Config config = SmallRun(config::Method::kSmorl);
  Learner first(LearnerOptionsFor(config, rl::RunShapeFor(config)));
  IngestAndUpdate(first, 20);
  first.TakePolicyWeights();
  first.agent().SaveCheckpoint(path, first.counters());  // the old contents

  Learner second(LearnerOptionsFor(config, rl::RunShapeFor(config)));
  second.LoadCheckpoint(path);
  EXPECT_FALSE(second.replay_restored());
  EXPECT_EQ(second.counters(), first.counters());
  EXPECT_EQ(second.agent().PolicyWeights(), first.agent().PolicyWeights());
  EXPECT_FALSE(second.CanUpdate()) << "empty replay";
  for (int i = 0; i < 5; ++i) second.Ingest(MakeEpisode(3, 20, 100 + i, 1));
  // the episode that completed the refill pays for 10 updates, plus the buffer of 4
  EXPECT_EQ(second.UpdatesAllowed(), 14u) << "no burst of updates after the refill";
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
  Learner learner(LearnerOptionsFor(c, rl::RunShapeFor(c)));
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

// Writing a checkpoint builds the file's bytes in memory (about twice its size, briefly); with
// the heap set up as every role process sets it up, that memory goes back to the system after
// instead of staying resident until the next checkpoint (the soak saw a learner's RSS step up by
// that much between checkpoints: +36 MB after four 15 MB checkpoints here without the setting).
TEST(LearnerCoreTest, ACheckpointsBuffersDoNotStayResident) {
  process::SetUpHeap();
  // on a thread of its own, as the learner loop
  std::thread([&] {
    const std::string path = ::testing::TempDir() + "/learner_core_resident.srics";
    config::Config config = SmallRun(config::Method::kSmorl);
    config.learner.replay_capacity = 200000;
    Learner learner(LearnerOptionsFor(config, rl::RunShapeFor(config)));
    for (int i = 0; i < 10000; ++i) ASSERT_EQ(learner.Ingest(MakeEpisode(3, 20, i, 1)), "");
    // a first round sizes what stays (the update's buffers; glibc mmaps the first big blocks)
    learner.SaveCheckpoint(path);
    for (int u = 0; u < 3 && learner.CanUpdate(); ++u) learner.Update();
    const long file_kb = static_cast<long>(std::filesystem::file_size(path) / 1024);
    ASSERT_GT(file_kb, 8 * 1024) << "the test needs a checkpoint of several MB";
    const long before = testing::MemoryInUseKb();
    long most = before;
    for (int i = 0; i < 4; ++i) {
      learner.SaveCheckpoint(path);
      // the learner loop trains between checkpoints: its buffers land above the freed ones
      for (int u = 0; u < 3 && learner.CanUpdate(); ++u) learner.Update();
      most = std::max(most, testing::MemoryInUseKb());
    }
    EXPECT_LT(most - before, file_kb / 4)
        << "resident " << before << " kB before, up to " << most << " kB after checkpoints of " << file_kb << " kB";
  }).join();
}

}  // namespace
}  // namespace srics::learner
