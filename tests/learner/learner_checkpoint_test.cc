// The learner's checkpoints (issue 15): the last K generations kept, a corrupt newest one set
// aside with a message naming it and what is wrong and the previous one loaded, a run whose
// checkpoints are all corrupt refused (never a silent start from scratch), and a write that
// fails on a full disk keeping the previous checkpoint while training goes on.

#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>

#include "common/links/in_memory_bus.h"
#include "learner/learner_loop.h"
#include "tests/common/files/test_files.h"
#include "tests/learner/learner_testing.h"

namespace srics::learner {
namespace {

namespace fs = std::filesystem;

using files::testing::ReadFile;

void FlipByte(const std::string& path, size_t from_end) {
  std::string data = ReadFile(path);
  data[data.size() - from_end] ^= 0x10;
  std::ofstream(path, std::ios::binary | std::ios::trunc) << data;
}

// A disk that fills up on demand.
class FillableDisk : public files::FileSystem {
 public:
  bool full = false;
  ssize_t Write(int fd, const void* data, size_t size) override {
    if (full) {
      errno = ENOSPC;
      return -1;
    }
    return FileSystem::Write(fd, data, size);
  }
};

class LearnerCheckpointTest : public ::testing::Test {
 protected:
  LearnerCheckpointTest() {
    path_ = (dir_ / "checkpoint.srics").string();
    log_ = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(200);
    previous_logger_ = spdlog::default_logger();
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("test", log_));
  }
  ~LearnerCheckpointTest() override { spdlog::set_default_logger(previous_logger_); }

  // SmallRun (warm-up 100, 0.5 updates per step) with a checkpoint every 10 updates, 3 kept.
  LearnerLoopOptions Options() const {
    config::Config c = testing::SmallRun(config::Method::kSmorl);
    c.run.total_env_steps = 100000;
    c.learner.checkpoint_every_updates = 10;
    c.learner.keep_checkpoints = 3;
    c.learner.publish_every_updates = 10;
    LearnerLoopOptions o = LearnerLoopOptionsFor(c, rl::RunShapeFor(c), path_);
    o.report_period_s = 0;
    o.final_weights_grace = std::chrono::milliseconds(0);
    return o;
  }

  // Episodes in, each followed by the updates it allows.
  static void Train(LearnerLoop& loop, links::ActorLink& actor, int first, int count) {
    for (int i = first; i < first + count; ++i) {
      ASSERT_TRUE(actor.PublishEpisode(testing::MakeEpisode(3, 20, i)));
      for (int k = 0; k < 100 && loop.Step() != StepResult::kIdle; ++k) {
      }
    }
  }

  // The updates a checkpoint file records.
  uint64_t UpdatesIn(const std::string& file) const {
    Learner probe(Options().learner);
    probe.LoadCheckpoint(file);
    return probe.counters().updates;
  }

  std::string Log() const {
    std::string text;
    for (const std::string& line : log_->last_formatted()) text += line;
    return text;
  }

  // A run trained over several checkpoints, then stopped (as by kill -9: no final one).
  void TrainedRun() {
    links::InMemoryBus bus;
    auto link = bus.LearnerEnd();
    auto actor = bus.ActorEnd(0);
    LearnerLoop loop(Options(), link.get());
    Train(loop, *actor, 0, 15);
    ASSERT_GE(loop.learner().counters().updates, 60u);
  }

  files::testing::ScratchFolder dir_{"srics-learner-ckpt"};
  std::string path_;
  std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> log_;
  std::shared_ptr<spdlog::logger> previous_logger_;
};

TEST_F(LearnerCheckpointTest, TheLastThreeAreKeptNewestFirst) {
  TrainedRun();
  const std::vector<std::string> generations = files::Generations(path_);
  ASSERT_EQ(generations, (std::vector<std::string>{path_, path_ + ".1", path_ + ".2"}));
  EXPECT_GT(UpdatesIn(path_), UpdatesIn(path_ + ".1"));
  EXPECT_GT(UpdatesIn(path_ + ".1"), UpdatesIn(path_ + ".2"));
  EXPECT_FALSE(fs::exists(path_ + ".3"));
  EXPECT_FALSE(fs::exists(path_ + ".tmp"));
}

TEST_F(LearnerCheckpointTest, ACorruptNewestIsSetAsideAndThePreviousOneLoaded) {
  TrainedRun();
  const uint64_t previous_updates = UpdatesIn(path_ + ".1");
  FlipByte(path_, 100);  // inside the replay: only the checksum tells

  links::InMemoryBus bus;
  auto link = bus.LearnerEnd();
  auto actor = bus.ActorEnd(0);
  LearnerLoop loop(Options(), link.get());
  ASSERT_NO_THROW(loop.Start());
  EXPECT_EQ(loop.learner().counters().updates, previous_updates);
  EXPECT_TRUE(fs::exists(path_ + ".corrupt"));
  EXPECT_FALSE(fs::exists(path_));
  const std::string log = Log();
  EXPECT_NE(log.find("checkpoint " + path_ + " is corrupt (checkpoint " + path_ +
                     ": checksum mismatch (corrupted)): "
                     "set aside as " +
                     path_ + ".corrupt"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("resumed from " + path_ + ".1 (an older checkpoint"), std::string::npos) << log;
  // it goes on and checkpoints as the newest again
  Train(loop, *actor, 100, 3);
  EXPECT_GT(UpdatesIn(path_), previous_updates);
}

// After a restart from a checkpoint, the episodes of its replay count as ingested: one
// delivered again (a foreign participant replaying a captured sample) is refused.
TEST_F(LearnerCheckpointTest, AnEpisodeOfTheRestoredReplayIsNotIngestedAgain) {
  TrainedRun();
  links::InMemoryBus bus;
  auto link = bus.LearnerEnd();
  auto actor = bus.ActorEnd(0);
  LearnerLoop loop(Options(), link.get());
  loop.Start();
  const uint64_t inserted = loop.learner().counters().transitions_inserted;
  ASSERT_GT(inserted, 0u);
  ASSERT_TRUE(actor->PublishEpisode(testing::MakeEpisode(3, 20, 0)));
  loop.Step();
  EXPECT_EQ(loop.duplicates_refused(), 1u);
  EXPECT_EQ(loop.learner().counters().transitions_inserted, inserted);
  ASSERT_TRUE(actor->PublishEpisode(testing::MakeEpisode(3, 20, 50)));
  loop.Step();
  EXPECT_EQ(loop.learner().counters().transitions_inserted, inserted + 20);
}

// Found by the soak: a learner killed before its first checkpoint started again at v1, and
// one killed twice after the same checkpoint published the same versions twice (v79..v92, then
// v79.. again): actors holding the higher version ignored the new weights, and two different
// weights carried one version. Versions now continue above every one published before.
TEST_F(LearnerCheckpointTest, PolicyVersionsNeverRepeatAcrossRestarts) {
  LearnerLoopOptions options = Options();
  options.learner.learner.checkpoint_every_updates = 100000;  // no checkpoint before the kills
  uint64_t highest = 0;
  for (int process = 0; process < 3; ++process) {
    links::InMemoryBus bus;
    auto link = bus.LearnerEnd();
    auto actor = bus.ActorEnd(0);
    LearnerLoop loop(options, link.get());
    loop.Start();
    const auto first = actor->PollWeights(0);
    ASSERT_TRUE(first.has_value());
    EXPECT_GT(first->version, highest) << "process " << process << " published a version seen before";
    Train(loop, *actor, 100 * process, 15);
    highest = actor->PollWeights(0)->version;
    ASSERT_GT(highest, first->version + 5) << "process " << process << " published a few versions";
  }  // killed: no final checkpoint
  EXPECT_FALSE(fs::exists(path_));
}

TEST_F(LearnerCheckpointTest, ARunWhoseCheckpointsAreAllCorruptIsRefusedAtEveryStart) {
  TrainedRun();
  for (const std::string& file : files::Generations(path_)) FlipByte(file, 50);
  for (int start = 0; start < 2; ++start) {
    links::InMemoryBus bus;
    auto link = bus.LearnerEnd();
    LearnerLoop loop(Options(), link.get());
    try {
      loop.Start();
      ADD_FAILURE() << "start " << start << ": started from scratch over a run's checkpoints";
    } catch (const nn::CheckpointError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("no usable checkpoint " + path_), std::string::npos) << message;
      EXPECT_NE(message.find(path_ + ".corrupt"), std::string::npos) << message;
      EXPECT_NE(message.find("remove them to start this run from scratch"), std::string::npos) << message;
    }
  }
  EXPECT_TRUE(files::Generations(path_).empty());
}

TEST_F(LearnerCheckpointTest, AFullDiskKeepsThePreviousCheckpointAndTrainingGoesOn) {
  FillableDisk disk;
  LearnerLoopOptions options = Options();
  options.file_system = &disk;
  links::InMemoryBus bus;
  auto link = bus.LearnerEnd();
  auto actor = bus.ActorEnd(0);
  LearnerLoop loop(options, link.get());
  Train(loop, *actor, 0, 8);
  ASSERT_TRUE(fs::exists(path_));
  const std::string before = ReadFile(path_);
  const uint64_t updates_before = loop.learner().counters().updates;

  disk.full = true;
  ASSERT_NO_THROW(Train(loop, *actor, 8, 4));
  EXPECT_GT(loop.learner().counters().updates, updates_before + 20) << "training went on";
  EXPECT_EQ(ReadFile(path_), before) << "the previous checkpoint is intact";
  EXPECT_FALSE(fs::exists(path_ + ".tmp"));
  const std::string log = Log();
  EXPECT_NE(log.find("checkpoint not written: cannot write " + path_ + ": writing"), std::string::npos) << log;
  EXPECT_NE(log.find("No space left on device; the previous " + path_ + " is kept, " + path_ + ".tmp removed"),
            std::string::npos)
      << log;

  disk.full = false;  // space again: the next one is written
  Train(loop, *actor, 12, 2);
  EXPECT_NE(ReadFile(path_), before);
  EXPECT_GT(UpdatesIn(path_), updates_before);
}

}  // namespace
}  // namespace srics::learner
