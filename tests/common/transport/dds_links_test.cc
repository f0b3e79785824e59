// The DDS links of common/transport/dds_links.h over real DDS on loopback, with no algorithm:
// what one link publishes arrives whole at the others, latest-value topics deliver only the
// newest, and what breaks the run's episode limits is refused, counted and does not block
// what follows. Each test process has its own domain and run id (from its pid).

#include "common/transport/dds_links.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <thread>

#include "common/rl/graph.h"
#include "tests/common/transport/test_samples.h"

namespace srics::transport {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

// Calls poll() until it returns a value or `timeout` passes.
template <typename Poll>
auto PollUntil(Poll poll, std::chrono::milliseconds timeout = 10s) -> decltype(poll()) {
  const auto deadline = Clock::now() + timeout;
  while (true) {
    if (auto value = poll()) return value;
    if (Clock::now() > deadline) return {};
    std::this_thread::sleep_for(5ms);
  }
}

// Takes episodes from a learner link until `count` arrived or `timeout` passed.
std::vector<rl::Episode> TakeFromLearner(DdsLearnerLink& link, size_t count, std::chrono::milliseconds timeout = 10s) {
  std::vector<rl::Episode> got;
  const auto deadline = Clock::now() + timeout;
  while (got.size() < count && Clock::now() < deadline) link.TakeEpisodes(&got, count - got.size(), 100ms);
  return got;
}

// Polls an episode source until `count` arrived or `timeout` passed.
std::vector<rl::Episode> TakeFromSource(DdsEpisodeSource& source, size_t count,
                                        std::chrono::milliseconds timeout = 10s) {
  std::vector<rl::Episode> got;
  const auto deadline = Clock::now() + timeout;
  while (got.size() < count && Clock::now() < deadline) source.Poll(100ms, &got);
  return got;
}

rl::Episode ExploreEpisode(uint64_t seed) {
  rl::Episode e = testing::MakeEpisode(seed);
  e.mode = rl::EpisodeMode::kExplore;
  e.subgoal_entity = -1;
  e.goal.clear();
  e.ancestor_mask = 0;
  e.subgoal_starts.clear();  // HAC's subgoal record belongs to training episodes
  e.subgoals.clear();
  e.subgoal_tests.clear();
  return e;
}

rl::WeightsUpdate Weights(uint64_t version) {
  rl::WeightsUpdate w;
  w.version = version;
  w.update_count = 100 * version;
  w.architecture = "attention-policy/test";
  for (int i = 0; i < 1000; ++i) w.parameters.push_back(static_cast<float>(version) + 0.001f * i);
  return w;
}

// A graph of the run's entity count in which the arm drives entity 1, which pushes entity 2.
rl::GraphUpdate Graph(uint64_t version) {
  constexpr int n = testing::kSampleKinds;
  rl::GraphUpdate g;
  g.version = version;
  g.graph.num_entities = n;
  g.graph.action_entity = 0;
  g.graph.adjacency.assign(n * n, 0);
  g.graph.adjacency[0 * n + 1] = 1;
  g.graph.adjacency[1 * n + 2] = 1;
  g.structure = rl::ComputeSubgoalStructure(g.graph);
  for (int i = 0; i < n * n; ++i) g.mean_weights.push_back(g.graph.adjacency[i] ? 0.5 + 0.01 * i : 0.001 * i);
  g.threshold = 0.25;
  g.held_out_loss = 0.125;
  g.training_updates = 1000 * version;
  g.episodes_used = 64;
  return g;
}

constexpr uint64_t kBudget = 9000;  // the run's budget of env steps (learner stats must carry it)

// An actor's episodes on their way to a learner and a graph service, each in a participant of
// its own; the actor waits (up to 10 s) until both readers matched.
struct EpisodeRoute {
  EpisodeRoute(const config::TransportConfig& config, const rl::EpisodeLimits& limits, uint32_t actor_id,
               bool graph_takes_training_episodes = false)
      : learner_side(config),
        graph_side(config),
        actor_side(config),
        learner(learner_side, limits),
        source(graph_side, limits, 100, graph_takes_training_episodes),
        actor(actor_side, actor_id, limits, kBudget, 10s) {}

  Participant learner_side, graph_side, actor_side;
  DdsLearnerLink learner;
  DdsEpisodeSource source;
  DdsActorLink actor;
};

class DdsLinksTest : public ::testing::Test {
 protected:
  config::TransportConfig config_ = testing::IsolatedTransportConfig("links");
  rl::EpisodeLimits limits_ = testing::SampleEpisodeLimits();
};

// Actors batch their episodes, each sent within transport.episode_batch_ms (0: unbatched); the
// link checks them, so the writer does not check again.
TEST(ActorEpisodeWriterOptionsTest, BatchedWithinTheConfiguredDelay) {
  config::TransportConfig config;
  WriterOptions options = ActorEpisodeWriterOptions(config);
  EXPECT_TRUE(options.batch);
  EXPECT_EQ(options.batch_delay, std::chrono::milliseconds(2));
  EXPECT_FALSE(options.validate);
  EXPECT_TRUE(options.stamp);
  config.episode_batch_ms = 0;
  options = ActorEpisodeWriterOptions(config);
  EXPECT_FALSE(options.batch);
  EXPECT_EQ(options.batch_delay, std::chrono::milliseconds(0));
}

TEST_F(DdsLinksTest, ActorEpisodesArriveWholeAtLearnerAndGraphSource) {
  EpisodeRoute route(config_, limits_, 3);
  const rl::Episode explore = ExploreEpisode(11);
  const rl::Episode train = testing::MakeEpisode(12);
  ASSERT_TRUE(route.actor.PublishEpisode(explore));
  ASSERT_TRUE(route.actor.PublishEpisode(train));

  const std::vector<rl::Episode> at_learner = TakeFromLearner(route.learner, 2);
  ASSERT_EQ(at_learner.size(), 2u);
  EXPECT_TRUE(at_learner[0] == explore);
  EXPECT_TRUE(at_learner[1] == train);
  EXPECT_EQ(at_learner[1].states, train.states);  // spelled out: no operator== hides a loss
  EXPECT_EQ(at_learner[1].layout, train.layout);
  // the graph service gets the explore episode only
  const std::vector<rl::Episode> at_source = TakeFromSource(route.source, 2, 1s);
  ASSERT_EQ(at_source.size(), 1u);
  EXPECT_TRUE(at_source[0] == explore);
  EXPECT_EQ(route.learner.rejected(), 0u);
  EXPECT_EQ(route.source.rejected(), 0u);
}

// graph.refine_after_publish: the graph service's source takes training episodes too.
TEST_F(DdsLinksTest, ARefiningGraphSourceGetsTrainingEpisodesToo) {
  EpisodeRoute route(config_, limits_, 4, /*graph_takes_training_episodes=*/true);
  const rl::Episode explore = ExploreEpisode(21);
  const rl::Episode train = testing::MakeEpisode(22);
  ASSERT_TRUE(route.actor.PublishEpisode(explore));
  ASSERT_TRUE(route.actor.PublishEpisode(train));
  const std::vector<rl::Episode> at_source = TakeFromSource(route.source, 2);
  ASSERT_EQ(at_source.size(), 2u);
  EXPECT_TRUE(at_source[0] == explore);
  EXPECT_TRUE(at_source[1] == train);
  EXPECT_EQ(TakeFromLearner(route.learner, 2).size(), 2u) << "the learner still gets both";
}

TEST_F(DdsLinksTest, WeightsGraphAndStatsArriveAsTheNewestOnly) {
  Participant learner_side(config_), graph_side(config_), actor_side(config_);
  DdsLearnerLink learner(learner_side, limits_);
  DdsGraphSink sink(graph_side);
  for (uint64_t v : {1, 2, 3}) learner.PublishWeights(Weights(v));
  for (uint64_t v : {1, 2}) sink.Publish(Graph(v));
  const rl::LearnerReport report{.updates = 500,
                                 .transitions_inserted = 4000,
                                 .training_env_steps = 3000,
                                 .budget_env_steps = 9000,
                                 .policy_version = 3};

  // a late joiner: transient-local, keep-last 1
  DdsActorLink actor(actor_side, 0, limits_, kBudget, 0ms);
  const auto weights = PollUntil([&] { return actor.PollWeights(0); });
  ASSERT_TRUE(weights.has_value());
  EXPECT_EQ(weights->version, 3u);
  EXPECT_EQ(weights->update_count, 300u);
  EXPECT_EQ(weights->architecture, "attention-policy/test");
  EXPECT_EQ(weights->parameters, Weights(3).parameters);
  const auto graph = PollUntil([&] { return actor.PollGraph(); });
  ASSERT_TRUE(graph.has_value());
  const rl::GraphUpdate want = Graph(2);
  EXPECT_EQ(graph->version, 2u);
  EXPECT_EQ(graph->graph.adjacency, want.graph.adjacency);
  EXPECT_EQ(graph->structure.ancestor_mask, want.structure.ancestor_mask);
  EXPECT_EQ(graph->structure.depth, want.structure.depth);
  ASSERT_EQ(graph->mean_weights.size(), want.mean_weights.size());
  for (size_t i = 0; i < want.mean_weights.size(); ++i)
    EXPECT_FLOAT_EQ(graph->mean_weights[i], want.mean_weights[i]);  // float on the wire
  EXPECT_DOUBLE_EQ(graph->threshold, 0.25);
  EXPECT_DOUBLE_EQ(graph->held_out_loss, 0.125);
  EXPECT_EQ(graph->training_updates, 2000u);
  EXPECT_EQ(graph->episodes_used, 64u);
  // stats are volatile: the learner publishes them again and again, the newest one counts
  const auto progress = PollUntil([&] {
    learner.PublishStats(report);
    return actor.PollLearner(100ms);
  });
  ASSERT_TRUE(progress.has_value());
  EXPECT_EQ(progress->updates, 500u);
  EXPECT_EQ(progress->training_env_steps, 3000u);
  EXPECT_EQ(progress->budget_env_steps, 9000u);
  EXPECT_FALSE(progress->budget_done());

  // nothing newer: nothing returned; an older version published again is not returned either
  EXPECT_FALSE(actor.PollWeights(3).has_value());
  learner.PublishWeights(Weights(2));
  std::this_thread::sleep_for(300ms);
  EXPECT_FALSE(actor.PollWeights(3).has_value());
  learner.PublishWeights(Weights(4));
  const auto newer = PollUntil([&] { return actor.PollWeights(3); });
  ASSERT_TRUE(newer.has_value());
  EXPECT_EQ(newer->version, 4u);
}

TEST_F(DdsLinksTest, GraphWhoseStructureDisagreesIsRefusedAndCounted) {
  Participant graph_side(config_), actor_side(config_);
  DdsGraphSink sink(graph_side);
  DdsActorLink actor(actor_side, 0, limits_, kBudget, 0ms);
  rl::GraphUpdate lying = Graph(1);
  lying.structure.ancestor_mask[2] = 0;  // entity 1 is an ancestor of 2 in the adjacency
  sink.Publish(lying);
  const auto refused = PollUntil([&]() -> std::optional<bool> {
    if (auto g = actor.PollGraph()) ADD_FAILURE() << "graph v" << g->version << " accepted";
    return actor.rejected() == 1 ? std::optional<bool>(true) : std::nullopt;
  });
  ASSERT_TRUE(refused.has_value()) << "the lying graph never arrived";
  sink.Publish(Graph(2));
  const auto graph = PollUntil([&] { return actor.PollGraph(); });
  ASSERT_TRUE(graph.has_value());
  EXPECT_EQ(graph->version, 2u);
  EXPECT_EQ(actor.rejected(), 1u);
}

TEST_F(DdsLinksTest, BrokenEpisodesAreRefusedCountedAndDoNotStopTheNextGoodOne) {
  Participant raw_side(config_), learner_side(config_), graph_side(config_);
  DdsLearnerLink learner(learner_side, limits_);
  DdsEpisodeSource source(graph_side, limits_, 100);
  WriterOptions unchecked;
  unchecked.validate = false;
  Writer<rl::Episode> raw(raw_side, unchecked);  // a foreign actor with no checks of its own
  ASSERT_TRUE(raw.WaitForReaders(2, 10s));

  rl::Episode oversized = testing::MakeEpisode(1, 20, testing::kSampleKinds + 1);  // more entities than the run's 8
  oversized.mode = rl::EpisodeMode::kExplore;
  rl::Episode wrong_layout = ExploreEpisode(2);  // velocities: 4 more floats per entity
  wrong_layout.layout.velocities = true;
  wrong_layout.states.resize(static_cast<size_t>(21) * 5 * wrong_layout.layout.entity_dim(), 0.0f);
  rl::Episode nan_state = ExploreEpisode(3);
  nan_state.states[9] = std::nanf("");
  rl::Episode far_away = ExploreEpisode(4);
  far_away.states[9] = 1e30f;  // finite: would poison the networks
  rl::Episode truncated = ExploreEpisode(5);
  truncated.actions.pop_back();
  const rl::Episode good = ExploreEpisode(6);
  for (const rl::Episode* e :
       std::initializer_list<const rl::Episode*>{&oversized, &wrong_layout, &nan_state, &far_away, &truncated, &good})
    ASSERT_EQ(raw.Write(*e), WriteResult::kSent);

  const std::vector<rl::Episode> at_learner = TakeFromLearner(learner, 1);
  ASSERT_EQ(at_learner.size(), 1u);
  EXPECT_TRUE(at_learner[0] == good);
  EXPECT_EQ(learner.rejected(), 5u);
  const std::vector<rl::Episode> at_source = TakeFromSource(source, 1);
  ASSERT_EQ(at_source.size(), 1u);
  EXPECT_TRUE(at_source[0] == good);
  EXPECT_EQ(source.rejected(), 5u);
  EXPECT_EQ(learner_side.total_rejected(), 5u);  // what NodeStatus reports
  // and nothing else comes
  std::vector<rl::Episode> more;
  EXPECT_EQ(learner.TakeEpisodes(&more, 10, 200ms), 0u);
}

TEST_F(DdsLinksTest, ActorDoesNotSendOwnEpisodesOutsideTheLimits) {
  EpisodeRoute route(config_, limits_, 0);  // both readers matched: a sent episode arrives
  rl::Episode bad = testing::MakeEpisode(1);
  bad.actions[0] = 1.5f;
  EXPECT_TRUE(route.actor.PublishEpisode(bad));  // refused, not a shutdown
  EXPECT_EQ(route.actor.rejected(), 1u);
  const rl::Episode good = testing::MakeEpisode(2);
  EXPECT_TRUE(route.actor.PublishEpisode(good));
  const std::vector<rl::Episode> got = TakeFromLearner(route.learner, 2, 1s);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_TRUE(got[0] == good);
  EXPECT_EQ(route.learner.rejected(), 0u);
}

TEST_F(DdsLinksTest, StatusOfEveryLinkIsPublishedUnderItsRole) {
  Participant monitor_side(config_), graph_side(config_), learner_side(config_);
  Reader<rl::NodeStatus> monitor(monitor_side);
  DdsGraphSink sink(graph_side);
  DdsLearnerLink learner(learner_side, limits_);
  rl::NodeReport report;
  report.phase = rl::NodePhase::kTraining;
  report.graph_version = 4;
  report.steps = 77;
  report.detail = "training: 10/20 episodes";
  sink.PublishStatus(report);
  report.phase = rl::NodePhase::kWaiting;
  learner.PublishStatus(report);
  std::map<std::string, rl::NodeStatus> seen;
  const auto deadline = Clock::now() + 10s;
  rl::NodeStatus status;
  while (seen.size() < 2 && Clock::now() < deadline)
    if (monitor.Take(&status, 100ms) == TakeStatus::kSample) seen[status.role] = status;
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen["graph"].report.phase, rl::NodePhase::kTraining);
  EXPECT_EQ(seen["graph"].report.graph_version, 4u);
  EXPECT_EQ(seen["graph"].report.steps, 77u);
  EXPECT_EQ(seen["graph"].report.detail, "training: 10/20 episodes");
  EXPECT_EQ(seen["learner"].report.phase, rl::NodePhase::kWaiting);
  EXPECT_EQ(seen["learner"].pid, static_cast<int32_t>(getpid()));
}

}  // namespace
}  // namespace srics::transport
