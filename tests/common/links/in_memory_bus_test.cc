// The in-memory bus: what each end reads, and Hold/Release, which the two-thread in-process
// schedule relies on: while held nothing published is visible to anyone (so what each thread
// reads cannot depend on the other's timing), and Release delivers the outboxes in one fixed
// order (graph service, actors by id, learner), whatever order they were filled in.

#include "common/links/in_memory_bus.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

namespace srics::links {
namespace {

// Records every publication the monitor would see, as "kind:who:value".
class Recorder : public BusObserver {
 public:
  void OnEval(const rl::EvalReport& r) override { seen.push_back("eval:" + std::to_string(r.actor_id)); }
  void OnLearnerStats(const rl::LearnerReport& r) override { seen.push_back("stats:" + std::to_string(r.updates)); }
  void OnGraph(const rl::GraphUpdate& g) override { seen.push_back("graph:" + std::to_string(g.version)); }
  void OnWeights(const rl::WeightsUpdate& w) override { seen.push_back("weights:" + std::to_string(w.version)); }
  void OnStatus(const std::string& role, uint32_t id, const rl::NodeReport&) override {
    seen.push_back("status:" + role + std::to_string(id));
  }
  std::vector<std::string> seen;
};

rl::Episode EpisodeOf(uint32_t actor, uint64_t id) {
  rl::Episode e;
  e.actor_id = actor;
  e.episode_id = id;
  e.mode = rl::EpisodeMode::kTrain;
  return e;
}

rl::WeightsUpdate Weights(uint64_t version) {
  rl::WeightsUpdate w;
  w.version = version;
  w.parameters = {1.0f, 2.0f};
  return w;
}

TEST(InMemoryBusTest, UnheldPublicationsAreSeenAtOnce) {
  Recorder recorder;
  InMemoryBus bus(&recorder);
  auto actor = bus.ActorEnd(0);
  auto learner = bus.LearnerEnd();
  learner->PublishWeights(Weights(3));
  ASSERT_TRUE(actor->PollWeights(0).has_value());
  EXPECT_FALSE(actor->PollWeights(0).has_value());  // each publication once
  actor->PublishEpisode(EpisodeOf(0, 7));
  std::vector<rl::Episode> got;
  EXPECT_EQ(learner->TakeEpisodes(&got, 10, std::chrono::milliseconds(0)), 1u);
  EXPECT_EQ(got.at(0).episode_id, 7u);
  EXPECT_EQ(recorder.seen, (std::vector<std::string>{"weights:3"}));
}

TEST(InMemoryBusTest, HeldPublicationsWaitAndArriveInTheFixedOrder) {
  Recorder recorder;
  InMemoryBus bus(&recorder);
  auto actor0 = bus.ActorEnd(0);
  auto actor1 = bus.ActorEnd(1);
  auto learner = bus.LearnerEnd();
  auto sink = bus.GraphSinkEnd();
  learner->PublishWeights(Weights(1));
  ASSERT_TRUE(actor0->PollWeights(0).has_value());
  recorder.seen.clear();

  bus.Hold();
  EXPECT_TRUE(bus.held());
  // filled in the reverse of the delivery order
  rl::LearnerReport stats;
  stats.updates = 5;
  stats.training_env_steps = 100;
  learner->PublishWeights(Weights(2));
  learner->PublishStats(stats);
  actor1->PublishEpisode(EpisodeOf(1, 1));
  rl::EvalReport eval;
  eval.actor_id = 1;
  actor1->PublishEval(eval);
  actor0->PublishEpisode(EpisodeOf(0, 1));
  actor0->PublishStatus(rl::NodeReport{});
  rl::GraphUpdate graph;
  graph.version = 1;
  sink->Publish(graph);

  // nothing of it is visible while held
  EXPECT_FALSE(actor0->PollWeights(1).has_value());
  EXPECT_FALSE(actor0->PollGraph().has_value());
  EXPECT_FALSE(actor0->PollLearner(std::chrono::milliseconds(0)).has_value());
  std::vector<rl::Episode> got;
  EXPECT_EQ(learner->TakeEpisodes(&got, 10, std::chrono::milliseconds(0)), 0u);
  EXPECT_EQ(bus.episodes_published(), 0u);
  EXPECT_TRUE(recorder.seen.empty());

  bus.Release();
  EXPECT_FALSE(bus.held());
  EXPECT_EQ(recorder.seen, (std::vector<std::string>{"graph:1", "status:actor0", "eval:1", "weights:2", "stats:5"}));
  const auto weights = actor0->PollWeights(1);
  ASSERT_TRUE(weights.has_value());
  EXPECT_EQ(weights->version, 2u);
  EXPECT_EQ(weights->parameters, (std::vector<float>{1.0f, 2.0f}));
  EXPECT_EQ(actor0->PollLearner(std::chrono::milliseconds(0))->training_env_steps, 100u);
  EXPECT_EQ(actor0->PollGraph()->version, 1u);
  // episodes in delivery order: actor 0's before actor 1's
  EXPECT_EQ(learner->TakeEpisodes(&got, 10, std::chrono::milliseconds(0)), 2u);
  EXPECT_EQ(got.at(0).actor_id, 0u);
  EXPECT_EQ(got.at(1).actor_id, 1u);
  EXPECT_EQ(bus.episodes_published(), 2u);

  // a released bus delivers at once again, and the outboxes were emptied
  actor0->PublishEpisode(EpisodeOf(0, 2));
  got.clear();
  EXPECT_EQ(learner->TakeEpisodes(&got, 10, std::chrono::milliseconds(0)), 1u);
  bus.Hold();
  bus.Release();
  EXPECT_EQ(bus.episodes_published(), 3u);
}

// A delivery that throws (a monitor's CSV on a full disk) does not stop the others: every
// outbox is emptied, every publication tried once, and the first error rethrown.
TEST(InMemoryBusTest, ReleaseTriesEveryPublicationAndRethrowsTheFirstError) {
  class Failing : public Recorder {
   public:
    void OnEval(const rl::EvalReport& r) override {
      Recorder::OnEval(r);
      throw std::runtime_error("disk full " + std::to_string(r.actor_id));
    }
  } observer;
  InMemoryBus bus(&observer);
  auto actor0 = bus.ActorEnd(0);
  auto actor1 = bus.ActorEnd(1);
  auto learner = bus.LearnerEnd();
  bus.Hold();
  rl::EvalReport eval;
  eval.actor_id = 1;
  actor1->PublishEval(eval);
  eval.actor_id = 0;
  actor0->PublishEval(eval);
  learner->PublishWeights(Weights(4));
  try {
    bus.Release();
    ADD_FAILURE() << "Release swallowed the error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "disk full 0");  // actor 0's outbox first
  }
  EXPECT_EQ(observer.seen, (std::vector<std::string>{"eval:0", "eval:1", "weights:4"}));
  ASSERT_TRUE(actor0->PollWeights(0).has_value());
  observer.seen.clear();
  bus.Hold();
  bus.Release();  // nothing again
  EXPECT_TRUE(observer.seen.empty());
}

// The two-thread schedule's use: the learner's end on one thread, the actors' on another, both
// held; what each reads is the state before the round, and the round's output is the same as
// when the two steps run one after the other.
TEST(InMemoryBusTest, TwoThreadsInAHeldRoundMatchOneThread) {
  auto round = [](bool threads) {
    Recorder recorder;
    InMemoryBus bus(&recorder);
    auto actor = bus.ActorEnd(0);
    auto learner = bus.LearnerEnd();
    actor->PublishEpisode(EpisodeOf(0, 0));  // the round before's
    std::vector<uint64_t> learner_took, actor_saw;
    auto learner_step = [&] {
      std::vector<rl::Episode> got;
      for (int i = 0; i < 200; ++i) {
        learner->TakeEpisodes(&got, 10, std::chrono::milliseconds(0));
        learner->PublishWeights(Weights(static_cast<uint64_t>(i + 1)));
      }
      for (const auto& e : got) learner_took.push_back(e.episode_id);
    };
    auto actor_step = [&] {
      for (uint64_t i = 1; i <= 200; ++i) {
        const auto w = actor->PollWeights(0);
        actor_saw.push_back(w ? w->version : 0);
        actor->PublishEpisode(EpisodeOf(0, i));
      }
    };
    bus.Hold();
    if (threads) {
      std::thread t(learner_step);
      actor_step();
      t.join();
    } else {
      learner_step();
      actor_step();
    }
    bus.Release();
    return std::make_tuple(learner_took, actor_saw, recorder.seen, bus.episodes_published());
  };
  const auto one = round(false);
  EXPECT_EQ(std::get<0>(one), (std::vector<uint64_t>{0}));     // only the round before's
  EXPECT_EQ(std::get<1>(one), std::vector<uint64_t>(200, 0));  // no weights within a round
  EXPECT_EQ(std::get<2>(one).size(), 200u);                    // every weights publication
  for (int repeat = 0; repeat < 20; ++repeat) EXPECT_EQ(round(true), one);
}

}  // namespace
}  // namespace srics::links
