// Issue 15: anything on the DDS domain can publish to every topic. Each test starts the
// receivers of a run (the DDS links, the actor loop, the graph service, the monitor) and a
// foreign participant of its own on the same loopback domain, which publishes the bad sample
// with a raw writer (no checks of its own). Each time the sample is refused, counted under its
// reason, changes no state, and the receiver goes on: it accepts the good sample that follows.

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <thread>

#include "actor/actor_loop.h"
#include "actor/env/rearrange_env.h"
#include "actor/episode_options.h"
#include "actor/explore_episode.h"
#include "common/config/config.h"
#include "common/nn/serialize.h"
#include "common/rl/agent_shape.h"
#include "common/rl/ground_truth.h"
#include "common/transport/dds_links.h"
#include "common/transport/graph_feed.h"
#include "common/transport/transport.h"
#include "common/transport/wire.h"
#include "deploy/monitor/display.h"
#include "deploy/monitor/monitor.h"
#include "graph_service/service.h"
#include "learner/learner_loop.h"
#include "tests/common/transport/test_samples.h"

namespace srics {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using transport::Participant;
using transport::Writer;
using transport::WriteResult;
using transport::WriterOptions;

// Calls poll() until it returns true or `timeout` passes.
template <typename Poll>
bool Eventually(Poll poll, std::chrono::milliseconds timeout = 10s) {
  const auto deadline = Clock::now() + timeout;
  while (Clock::now() < deadline) {
    if (poll()) return true;
    std::this_thread::sleep_for(5ms);
  }
  return poll();
}

// A small SRICS run on Rearrange 1 (the arm and one puck), on this test's own domain and run.
config::Config RunConfig() {
  config::Config c = config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml",
                                        {"graph.episodes=4", "graph.held_out_fraction=0.25", "actors.count=2",
                                         "actors.evaluators=1", "actors.eval_episodes=2", "run.total_env_steps=5000"});
  const config::TransportConfig isolated = transport::testing::IsolatedTransportConfig("foreign");
  c.transport.domain_id = isolated.domain_id;
  c.transport.run_id = isolated.run_id;
  c.transport.rejected_log_interval_s = 1;
  return c;
}

// A writer that sends whatever it is given (a foreign participant with no checks): it stamps
// the envelope (and the weights' checksum) of its participant unless told not to.
WriterOptions Raw(bool stamp = true) {
  WriterOptions o;
  o.validate = false;
  o.stamp = stamp;
  return o;
}

uint64_t Rejections(const Participant& p, const std::string& counter) {
  const auto all = p.rejections();
  const auto it = all.find(counter);
  return it == all.end() ? 0 : it->second;
}

rl::GraphUpdate GroundTruth(const config::Config& config, uint64_t version) {
  rl::GraphUpdate g;
  g.version = version;
  g.graph = rl::GroundTruthGraph(config.env);
  g.structure = rl::ComputeSubgoalStructure(g.graph);
  g.mean_weights.assign(static_cast<size_t>(g.graph.num_entities) * g.graph.num_entities, 0.0);
  return g;
}

// Weights a learner of this run would publish for `options`' policy.
rl::WeightsUpdate WeightsFor(const actor::ActorOptions& options, uint64_t version, uint64_t seed) {
  nn::Rng rng(seed);
  rl::PolicyNetwork<float> policy("policy", options.policy, rng);
  return {version, version * 10, rl::PolicySignature(policy), nn::Flatten(policy.Parameters())};
}

class ForeignSamplesTest : public ::testing::Test {
 protected:
  config::Config config_ = RunConfig();
  rl::EpisodeLimits limits_ = rl::EpisodeLimitsFor(config_.env);

  // Actor 1 of this run, playing no explore episodes while it waits for weights and a graph.
  actor::ActorOptions ActorWithoutExploreOptions() const {
    actor::ActorOptions options = actor::ActorOptionsFor(config_, rl::RunShapeFor(config_), 1);
    options.explore_while_waiting_s = 0;
    return options;
  }
};

// Calls `f` and says how long it took.
template <typename F>
double SecondsOf(F f) {
  const auto start = Clock::now();
  f();
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A real explore episode of this run's environment.
rl::Episode ExploreEpisode(const config::Config& config, uint64_t seed) {
  auto env = env::MakeRearrangeEnv(config.env);
  nn::Rng rng(seed);
  auto episode = actor::RunExploreEpisode(*env, actor::ExploreOptionsFor(config), seed, rng);
  if (!episode) throw std::runtime_error("unstable explore episode");
  episode->actor_id = 7;
  episode->episode_id = seed;
  return *episode;
}

// A complete graph of 16 entities hung the learner and the actors (every simple path was
// enumerated before the entity count was checked): now refused at once for the run's entity
// count; its version of 2^62 does not hide the graph service's v1 that follows. A feed that
// takes any entity count computes the structure of the complete graph in milliseconds.
TEST_F(ForeignSamplesTest, CompleteGraphOf16EntitiesIsRefusedAtOnceAndTheRunsGraphFollows) {
  Participant foreign(config_.transport), learner_side(config_.transport), actor_side(config_.transport),
      graph_side(config_.transport), any_side(config_.transport), monitor_side(config_.transport);
  transport::DdsLearnerLink learner(learner_side, limits_);
  transport::DdsActorLink actor(actor_side, 1, limits_, config_.run.total_env_steps, 0ms);
  transport::GraphFeed any(any_side, 0);
  transport::Reader<rl::NodeStatus> statuses(monitor_side);
  Writer<rl::GraphUpdate> raw(foreign, Raw());
  ASSERT_TRUE(raw.WaitForReaders(3, 10s));
  ASSERT_EQ(raw.Write(transport::testing::MakeCompleteGraph(16, uint64_t{1} << 62)), WriteResult::kSent);

  std::optional<rl::GraphUpdate> any_graph;
  double slowest_poll = 0;
  ASSERT_TRUE(Eventually([&] {
    slowest_poll = std::max(slowest_poll, SecondsOf([&] {
                              if (auto g = learner.PollGraph())
                                ADD_FAILURE() << "the learner took graph v" << g->version;
                              if (auto g = actor.PollGraph()) ADD_FAILURE() << "the actor took graph v" << g->version;
                              if (!any_graph) any_graph = any.PollNewest();
                            }));
    return Rejections(learner_side, "graph.entities") == 1 && Rejections(actor_side, "graph.entities") == 1 &&
           any_graph.has_value();
  })) << "learner "
      << Rejections(learner_side, "graph.entities") << ", actor " << Rejections(actor_side, "graph.entities")
      << ", any " << any_graph.has_value();
  EXPECT_LT(slowest_poll, 1.0);
  EXPECT_EQ(any_graph->structure.depth[5], 16);

  // the run's graph, version 1, still arrives at both
  transport::DdsGraphSink sink(graph_side);
  const rl::GraphUpdate truth = GroundTruth(config_, 1);
  sink.Publish(truth);
  std::optional<rl::GraphUpdate> at_learner, at_actor;
  ASSERT_TRUE(Eventually([&] {
    if (!at_learner) at_learner = learner.PollGraph();
    if (!at_actor) at_actor = actor.PollGraph();
    return at_learner && at_actor;
  }));
  EXPECT_EQ(at_learner->version, 1u);
  EXPECT_EQ(at_actor->version, 1u);
  EXPECT_EQ(at_actor->graph.adjacency, truth.graph.adjacency);
  EXPECT_EQ(at_actor->structure.ancestor_mask, truth.structure.ancestor_mask);
  EXPECT_EQ(Rejections(actor_side, "graph.entities"), 1u);

  // the refusal shows in the actor's NodeStatus, per reason
  rl::NodeReport report;
  report.detail = "exploring";
  actor.PublishStatus(report);
  rl::NodeStatus status;
  ASSERT_EQ(statuses.Take(&status, 10s), transport::TakeStatus::kSample);
  EXPECT_EQ(status.report.detail, "exploring | rejected: graph.entities=1");
  EXPECT_EQ(status.report.dropped, 1u);
}

// A refused PolicyWeights sample advanced the actor's version: one with a huge version froze
// the weights for the rest of the run. Huge (finite) weights made the environment throw in
// every actor. Now: another architecture, another size and huge magnitudes are refused and
// counted, the learner's v1 that follows is taken; weights at the bound are taken and the
// actor goes on training (an overflowing policy costs an episode, never the actor:
// ActorLoopTest.NonFiniteActionsDropTheEpisodeInsteadOfThrowing).
TEST_F(ForeignSamplesTest, RefusedWeightsWithAHugeVersionDoNotFreezeTheActor) {
  Participant foreign(config_.transport), learner_side(config_.transport), actor_side(config_.transport),
      graph_side(config_.transport);
  transport::DdsLearnerLink learner(learner_side, limits_);
  transport::DdsActorLink link(actor_side, 1, limits_, config_.run.total_env_steps, 0ms);
  const actor::ActorOptions options = ActorWithoutExploreOptions();
  actor::ActorLoop actor(options, &link);
  Writer<rl::WeightsUpdate> raw(foreign, Raw());
  ASSERT_TRUE(raw.WaitForReaders(1, 10s));
  auto refused = [&](const char* counter) {
    const auto& r = actor.counters().rejections;
    return (r.count(counter) ? r.at(counter) : 0) + Rejections(actor_side, counter);
  };

  rl::WeightsUpdate other = WeightsFor(options, uint64_t{1} << 62, 5);
  other.architecture = "attention-policy/another-network";
  ASSERT_EQ(raw.Write(other), WriteResult::kSent);
  ASSERT_TRUE(Eventually([&] {
    actor.Step();
    return refused("weights.architecture") == 1;
  }));
  rl::WeightsUpdate shorter = WeightsFor(options, uint64_t{1} << 61, 5);
  shorter.parameters.pop_back();
  ASSERT_EQ(raw.Write(shorter), WriteResult::kSent);
  ASSERT_TRUE(Eventually([&] {
    actor.Step();
    return refused("weights.size") == 1;
  }));
  rl::WeightsUpdate huge = WeightsFor(options, uint64_t{1} << 60, 5);
  huge.parameters[3] = 1e30f;  // finite: passed the old checks
  ASSERT_EQ(raw.Write(huge), WriteResult::kSent);
  ASSERT_TRUE(Eventually([&] {
    actor.Step();
    return refused("weights.magnitude") == 1;
  }));
  EXPECT_EQ(actor.policy_version(), 0u);

  // the learner's first weights are taken: no refused version hid them
  learner.PublishWeights(WeightsFor(options, 1, 11));
  ASSERT_TRUE(Eventually([&] {
    actor.Step();
    return actor.policy_version() == 1u;
  }));

  // weights at the bound, the largest the contract allows: the actor trains on with them
  transport::DdsGraphSink sink(graph_side);
  sink.Publish(GroundTruth(config_, 1));
  ASSERT_TRUE(Eventually([&] {
    actor.Step();
    return actor.graph_version() == 1u;
  }));
  rl::WeightsUpdate extreme = WeightsFor(options, 2, 12);
  for (float& w : extreme.parameters) w = rl::kMaxAbsParameter;
  learner.PublishWeights(extreme);
  ASSERT_TRUE(Eventually([&] {
    EXPECT_NO_THROW(actor.Step());
    return actor.policy_version() == 2u;
  }));
  for (int i = 0; i < 3; ++i) EXPECT_NO_THROW(actor.Step());
  learner.PublishWeights(WeightsFor(options, 3, 13));
  const uint64_t episodes_before = actor.counters().episodes;
  ASSERT_TRUE(Eventually([&] {
    actor.Step();
    return actor.policy_version() == 3u && actor.counters().episodes > episodes_before;
  }));
  bool trained_with_v3 = false;
  EXPECT_TRUE(Eventually([&] {
    std::vector<rl::Episode> got;
    learner.TakeEpisodes(&got, 1000, 10ms);
    for (const rl::Episode& e : got) trained_with_v3 |= e.mode == rl::EpisodeMode::kTrain && e.policy_version == 3;
    return trained_with_v3;
  }));
}

// A LearnerStats sample from anyone ended every actor. Now a sample of another run is
// ignored, one with another budget or counters that cannot be the learner's is refused and
// counted, and the actor ends only on the run's learner saying the budget is done.
TEST_F(ForeignSamplesTest, ForeignLearnerStatsDoNotEndTheActor) {
  config::TransportConfig elsewhere = config_.transport;
  elsewhere.run_id = "another-run";
  Participant foreign(config_.transport), other_run(elsewhere), learner_side(config_.transport),
      actor_side(config_.transport);
  transport::DdsLearnerLink learner(learner_side, limits_);
  transport::DdsActorLink link(actor_side, 1, limits_, config_.run.total_env_steps, 0ms);
  const actor::ActorOptions options = ActorWithoutExploreOptions();
  actor::ActorLoop actor(options, &link);
  Writer<rl::LearnerReport> raw(foreign, Raw()), other(other_run, Raw());
  ASSERT_TRUE(raw.WaitForReaders(1, 10s));
  ASSERT_TRUE(other.WaitForReaders(1, 10s));
  const uint64_t budget = config_.run.total_env_steps;
  const rl::LearnerReport done{.updates = 4000,
                               .transitions_inserted = budget,
                               .training_env_steps = budget,
                               .budget_env_steps = budget,
                               .replay_size = budget,
                               .policy_version = 40};

  auto step_until = [&](auto condition) {
    return Eventually([&] {
      EXPECT_NE(actor.Step(), actor::StepResult::kDone) << "a foreign sample ended the actor";
      return condition();
    });
  };
  // of another run: ignored (counted apart)
  ASSERT_EQ(other.Write(done), WriteResult::kSent);
  ASSERT_TRUE(step_until([&] { return actor_side.counters(transport::TopicId::kLearnerStats).other_run == 1; }));
  // another budget
  rl::LearnerReport wrong_budget = done;
  wrong_budget.budget_env_steps = wrong_budget.training_env_steps = wrong_budget.transitions_inserted = 100;
  ASSERT_EQ(raw.Write(wrong_budget), WriteResult::kSent);
  ASSERT_TRUE(step_until([&] { return Rejections(actor_side, "stats.implausible") == 1; }));
  // the run's budget "done" with fewer transitions than training steps, then a huge step count
  // (it used to make an evaluating actor loop for as long as the count is large)
  rl::LearnerReport inconsistent = done;
  inconsistent.transitions_inserted = 10;
  ASSERT_EQ(raw.Write(inconsistent), WriteResult::kSent);
  ASSERT_TRUE(step_until([&] { return Rejections(actor_side, "stats.implausible") == 2; }));
  rl::LearnerReport beyond = done;
  beyond.training_env_steps = beyond.transitions_inserted = uint64_t{1} << 62;
  ASSERT_EQ(raw.Write(beyond), WriteResult::kSent);
  ASSERT_TRUE(step_until([&] { return Rejections(actor_side, "stats.implausible") == 3; }));

  // the run's learner says the budget is done: the actor ends
  ASSERT_TRUE(Eventually([&] {
    learner.PublishStats(done);
    return actor.Step() == actor::StepResult::kDone;
  }));
}

// Huge finite states turned the learner's weights into NaN. Now such an episode is refused
// on arrival (the run's limits: positions within 10 m) and counted; the next one is stored.
TEST_F(ForeignSamplesTest, EpisodeWithHugeFiniteStatesIsRefusedAndTheLearnerGoesOn) {
  Participant foreign(config_.transport), learner_side(config_.transport);
  transport::DdsLearnerLink link(learner_side, limits_);
  learner::LearnerLoop loop(learner::LearnerLoopOptionsFor(config_, rl::RunShapeFor(config_), ""), &link);
  Writer<rl::Episode> raw(foreign, Raw());
  ASSERT_TRUE(raw.WaitForReaders(1, 10s));
  const rl::Episode good = ExploreEpisode(config_, 1);
  rl::Episode far = good;
  far.states[far.layout.position_offset(1) + far.layout.state_size() * 3] = 1e6f;
  ASSERT_EQ(raw.Write(far), WriteResult::kSent);
  ASSERT_EQ(raw.Write(good), WriteResult::kSent);
  ASSERT_TRUE(Eventually([&] {
    loop.Step(50ms);
    return loop.learner().counters().episodes_accepted == 1;
  }));
  EXPECT_EQ(Rejections(learner_side, "episode.limits"), 1u);
  EXPECT_EQ(link.rejected(), 1u);
  EXPECT_EQ(loop.learner().counters().transitions_inserted, static_cast<uint64_t>(good.num_steps));
}

// The graph service took its data set's layout from the first explore episode it received,
// from anyone: one foreign episode (two arms: kinds 0, 0, within the run's limits) made it
// refuse every episode of the run. Now the layout is the run's (from its config).
TEST_F(ForeignSamplesTest, GraphServiceLayoutIsTheRunsNotTheFirstEpisodes) {
  Participant foreign(config_.transport), graph_side(config_.transport);
  transport::DdsEpisodeSource source(graph_side, limits_, 100);
  transport::DdsGraphSink sink(graph_side);
  graph_service::ServiceOptions options;
  options.render_pictures = false;
  options.limits = limits_;
  const rl::EnvironmentShape shape = rl::FullEnvironmentShapeFor(config_.env);
  options.shape = graph_service::DatasetShape{shape.layout, shape.entity_kinds, shape.action_dim};
  graph_service::GraphService service(config_.graph, options, &source, &sink, nullptr);
  Writer<rl::Episode> raw(foreign, Raw());
  ASSERT_TRUE(raw.WaitForReaders(1, 10s));

  rl::Episode two_arms = ExploreEpisode(config_, 100);
  ASSERT_EQ(two_arms.entity_kinds, (std::vector<uint16_t>{0, 1}));
  two_arms.entity_kinds = {0, 0};
  const int d = two_arms.layout.entity_dim();
  for (int t = 0; t <= two_arms.num_steps; ++t) {  // entity 1's one-hot says kind 0
    float* token = two_arms.states.data() + static_cast<size_t>(t) * two_arms.layout.state_size() + d;
    token[0] = 1.0f;
    token[1] = 0.0f;
  }
  ASSERT_EQ(rl::ValidateEpisode(two_arms, limits_), "") << "within the run's limits";
  ASSERT_EQ(raw.Write(two_arms), WriteResult::kSent);
  ASSERT_TRUE(Eventually([&] {
    service.Step(20ms);
    return service.progress().dropped == 1;
  }));
  EXPECT_NE(service.progress().last_drop_reason.find("kinds"), std::string::npos)
      << service.progress().last_drop_reason;

  for (uint64_t seed = 1; seed <= 4; ++seed) ASSERT_EQ(raw.Write(ExploreEpisode(config_, seed)), WriteResult::kSent);
  ASSERT_TRUE(Eventually([&] {
    service.Step(20ms);
    return service.progress().episodes == config_.graph.episodes;
  })) << service.progress().episodes
      << " episodes, last drop: " << service.progress().last_drop_reason;
  EXPECT_EQ(service.progress().dropped, 1);
}

// Found by the soak: a learner or actor that (re)started after a stranger had published a
// graph got the stranger's sample instead of the graph service's. Both are transient-local
// samples of the run's one instance; with one history slot per instance in the reader, the
// later of the two historical samples displaced the other, the stranger's was refused, and the
// run's graph never came (the graph service publishes only on a change): the restarted learner
// waited for the graph for the rest of the run. The same for the weights until the learner's
// next publication. Each late joiner here must get the run's graph v1 and weights v1.
TEST_F(ForeignSamplesTest, ALateJoinerGetsTheRunsGraphAndWeightsBesideAStrangersSamples) {
  Participant foreign(config_.transport), graph_side(config_.transport), learner_side(config_.transport);
  transport::DdsGraphSink sink(graph_side);
  transport::DdsLearnerLink learner(learner_side, limits_);
  const actor::ActorOptions options = actor::ActorOptionsFor(config_, rl::RunShapeFor(config_), 1);
  sink.Publish(GroundTruth(config_, 1));
  learner.PublishWeights(WeightsFor(options, 1, 11));
  std::this_thread::sleep_for(200ms);
  Writer<rl::GraphUpdate> raw_graph(foreign, Raw());
  Writer<rl::WeightsUpdate> raw_weights(foreign, Raw());
  ASSERT_EQ(raw_graph.Write(transport::testing::MakeCompleteGraph(16, uint64_t{1} << 62)), WriteResult::kSent);
  rl::WeightsUpdate huge = WeightsFor(options, uint64_t{1} << 62, 5);
  huge.parameters[3] = 1e30f;
  ASSERT_EQ(raw_weights.Write(huge), WriteResult::kSent);
  std::this_thread::sleep_for(200ms);
  for (int joiner = 0; joiner < 4; ++joiner) {
    Participant actor_side(config_.transport);
    transport::DdsActorLink actor(actor_side, 1, limits_, config_.run.total_env_steps, 0ms);
    std::this_thread::sleep_for(300ms);  // both writers' historical samples are in the reader
    std::optional<rl::GraphUpdate> graph;
    std::optional<rl::WeightsUpdate> weights;
    EXPECT_TRUE(Eventually(
        [&] {
          if (!graph) graph = actor.PollGraph();
          if (!weights) weights = actor.PollWeights(0);
          return graph && weights;
        },
        5s))
        << "joiner " << joiner << ": graph " << graph.has_value() << ", weights " << weights.has_value()
        << ", graphs refused " << Rejections(actor_side, "graph.entities");
    if (graph) EXPECT_EQ(graph->version, 1u);
    if (weights) EXPECT_EQ(weights->version, 1u);
  }
}

// The launcher's monitor wrote any LearnerStats of the run into learner.csv and showed any
// graph (found by the soak: a stranger's stats with 2^62 steps and policy v10 between the
// learner's v1 rows, a 16-entity graph at version 2^62 on the display). Told its run's budget
// and entity count, it refuses both, counts them, and takes the run's own that follow.
TEST_F(ForeignSamplesTest, LaunchersMonitorRefusesStatsAndGraphsThatCannotBeTheRuns) {
  Participant foreign(config_.transport), learner_side(config_.transport), graph_side(config_.transport),
      monitor_side(config_.transport);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("monitor-" + config_.transport.run_id);
  std::filesystem::create_directories(dir);
  const uint64_t budget = config_.run.total_env_steps;
  {
    monitor::MonitorOptions options{.weights = false, .csv_dir = dir.string()};
    options.budget_env_steps = budget;
    options.num_entities = 2;
    monitor::Monitor monitor(monitor_side, options);
    transport::DdsLearnerLink learner(learner_side, limits_);
    transport::DdsGraphSink sink(graph_side);
    Writer<rl::LearnerReport> raw_stats(foreign, Raw());
    Writer<rl::GraphUpdate> raw_graph(foreign, Raw());
    ASSERT_TRUE(raw_stats.WaitForReaders(1, 10s));
    ASSERT_TRUE(raw_graph.WaitForReaders(1, 10s));
    rl::LearnerReport beyond = transport::testing::MakeLearnerStats(1);
    beyond.transitions_inserted = beyond.training_env_steps = uint64_t{1} << 62;
    beyond.budget_env_steps = budget;
    ASSERT_EQ(raw_stats.Write(beyond), WriteResult::kSent);
    ASSERT_EQ(raw_graph.Write(transport::testing::MakeCompleteGraph(16, uint64_t{1} << 62)), WriteResult::kSent);
    ASSERT_TRUE(Eventually([&] {
      monitor.Poll(20ms);
      return Rejections(monitor_side, "stats.implausible") == 1 && Rejections(monitor_side, "graph.entities") == 1;
    })) << "stats "
        << Rejections(monitor_side, "stats.implausible") << ", graphs " << Rejections(monitor_side, "graph.entities");
    const auto& runs = monitor.state().runs;
    auto run = runs.find(config_.transport.run_id);
    EXPECT_TRUE(run == runs.end() || (!run->second.learner && !run->second.graph));

    const rl::LearnerReport real{.updates = 10,
                                 .transitions_inserted = 200,
                                 .training_env_steps = 200,
                                 .budget_env_steps = budget,
                                 .replay_size = 200,
                                 .policy_version = 2};
    learner.PublishStats(real);
    sink.Publish(GroundTruth(config_, 1));
    ASSERT_TRUE(Eventually([&] {
      monitor.Poll(20ms);
      run = monitor.state().runs.find(config_.transport.run_id);
      return run != monitor.state().runs.end() && run->second.learner && run->second.graph;
    }));
    EXPECT_EQ(run->second.learner->policy_version, 2u);
    EXPECT_EQ(run->second.graph->version, 1u);
  }
  std::ifstream csv(dir / "learner.csv");
  std::string line;
  int rows = 0;
  while (std::getline(csv, line)) rows += line.rfind("wall_time", 0) != 0;
  EXPECT_EQ(rows, 1) << "only the run's learner in learner.csv";
  std::filesystem::remove_all(dir);
}

// The monitor printed peer strings raw: a NodeStatus could drive the terminal (clear it, set
// its title, move the cursor). Now every string is shown as printable ASCII.
TEST_F(ForeignSamplesTest, MonitorShowsForeignStringsWithoutControlCharacters) {
  Participant foreign(config_.transport), monitor_side(config_.transport);
  monitor::Monitor monitor(monitor_side, {.weights = false});
  Writer<rl::NodeStatus> raw(foreign, Raw());
  ASSERT_TRUE(raw.WaitForReaders(1, 10s));
  rl::NodeStatus status;
  status.role = "actor\x1b[31m";
  status.node_id = 3;
  status.host = "lab\r\nhost";
  status.report.detail =
      "\x1b]0;owned\x07\x1b[2J\xc2\x9b"
      "2J done";
  status.report.phase = rl::NodePhase::kTraining;
  ASSERT_EQ(raw.Write(status), WriteResult::kSent);
  ASSERT_TRUE(Eventually([&] {
    monitor.Poll(50ms);
    return !monitor.state().nodes.empty();
  }));
  const rl::NodeStatus& shown = monitor.state().nodes.begin()->second.status;
  EXPECT_EQ(shown.role, "actor?[31m");
  EXPECT_EQ(shown.host, "lab??host");
  EXPECT_EQ(shown.report.detail, "?]0;owned??[2J??2J done");
  const std::string screen = monitor::Render(monitor.state(), Clock::now(), {});
  for (char c : screen)
    EXPECT_TRUE(c == '\n' || (c >= 0x20 && c <= 0x7e)) << "byte " << static_cast<int>(static_cast<unsigned char>(c));
}

}  // namespace
}  // namespace srics
