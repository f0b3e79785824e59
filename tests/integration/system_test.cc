// The distributed system end to end: real srics-graph, srics-learner and srics-actor
// processes over loopback DDS, and real faults (kill -9, restarts, a foreign participant).

#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <fstream>

#include "tests/integration/system_harness.h"

namespace srics::testing {
namespace {

bool Increasing(const std::vector<uint64_t>& v) {
  for (size_t i = 1; i < v.size(); ++i)
    if (v[i] <= v[i - 1]) return false;
  return true;
}

TEST(SystemTest, GraphServiceLearnerAndTwoActorsLearnAndFinish) {
  System system("e2e");
  system.StartAll(2);
  ASSERT_TRUE(system.WaitUntil([&] { return system.graph.has_value(); }, 120s)) << system.Output("graph");
  EXPECT_GE(system.graph->version, 1u);
  EXPECT_TRUE(std::filesystem::exists(system.run_dir() + "/graph.json"));
  ASSERT_TRUE(system.WaitUntil([&] { return system.stats && system.stats->updates > 0; }, 60s))
      << system.Output("learner");
  // an actor process stays small: MuJoCo, one policy network, one episode at a time
  for (const char* actor : {"actor-0", "actor-1"}) {
    const double mb = system.ResidentMb(actor);
    EXPECT_GT(mb, 0) << actor;
    EXPECT_LT(mb, 150) << actor << " resident memory";
    RecordProperty(std::string(actor) + "_rss_mb", std::to_string(mb));
  }
  // the run ends by itself: the learner reaches its budget, actors finish after a last evaluation
  ASSERT_NO_FATAL_FAILURE(system.ExpectRolesFinish({"learner", "actor-0", "actor-1"}, 240s));
  system.WaitUntil([] { return false; }, 1s);
  EXPECT_GT(system.latest_weights, 1u);
  EXPECT_TRUE(Increasing(system.weight_versions));
  ASSERT_TRUE(system.stats.has_value());
  EXPECT_GE(system.stats->training_env_steps, system.config().run.total_env_steps);
  EXPECT_EQ(system.stats->episodes_rejected, 0u);
  // evaluations: the passive baseline first, then the policy, on every entity
  ASSERT_GE(system.evals.size(), 2u);
  EXPECT_EQ(system.evals.front().policy_version, 0u);
  EXPECT_GT(system.evals.back().policy_version, 0u);
  EXPECT_EQ(system.evals.back().summary.entity_distance.size(), 3u);
  EXPECT_TRUE(std::filesystem::exists(system.run_dir() + "/checkpoint.srics"));
}

TEST(SystemTest, KilledActorLeavesNoPartialEpisodeAndResumesWithLatestWeightsAndGraph) {
  System system("kill-actor", {"run.total_env_steps=1000000"});
  system.StartAll(2);
  ASSERT_TRUE(system.WaitUntil([&] { return system.stats && system.stats->updates > 50; }, 180s))
      << system.Output("learner");
  // mid-episode: an actor spends nearly all its time inside episodes
  system.Crash("actor-1");
  const uint64_t updates_at_kill = system.stats->updates;
  ASSERT_TRUE(system.WaitUntil([&] { return system.stats->updates > updates_at_kill + 20; }, 30s))
      << "the learner stopped training after an actor died\n"
      << system.Output("learner");
  EXPECT_TRUE(system.child("learner").running());
  // restart: within 2 s it reports the latest weights and the graph
  const uint64_t graph_version = system.graph->version;
  system.Start("actor-1");
  const auto restarted = std::chrono::steady_clock::now();
  ASSERT_TRUE(system.WaitUntil(
      [&] {
        auto it = system.nodes.find("actor-1");
        return it != system.nodes.end() && it->second.pid == system.child("actor-1").pid() &&
               it->second.report.graph_version == graph_version && it->second.report.policy_version > 0 &&
               it->second.report.policy_version + 3 >= system.latest_weights;
      },
      10s))
      << system.Output("actor-1");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - restarted).count();
  EXPECT_LT(seconds, 2.5) << "restarted actor took " << seconds << " s to get the weights and graph";
  EXPECT_EQ(system.stats->episodes_rejected, 0u) << "a partial episode reached the learner";
  EXPECT_EQ(system.nodes["learner-0"].report.dropped, 0u);
}

TEST(SystemTest, LearnerRestartsFromItsCheckpointAndVersionsKeepIncreasing) {
  System system("kill-learner", {"run.total_env_steps=1000000", "learner.checkpoint_every_updates=100"});
  system.StartAll(2);
  ASSERT_TRUE(system.WaitUntil([&] { return system.stats && system.stats->updates > 250; }, 180s))
      << system.Output("learner");
  system.Crash("learner");
  const uint64_t updates_before = system.stats->updates;
  const uint64_t weights_before = system.latest_weights;
  system.Start("learner");
  ASSERT_TRUE(system.WaitUntil([&] { return system.latest_weights > weights_before + 2; }, 60s))
      << system.Output("learner");
  ASSERT_TRUE(system.WaitUntil([&] { return system.stats->updates > updates_before; }, 120s))
      << system.Output("learner");
  EXPECT_TRUE(Increasing(system.weight_versions)) << "weight versions went backwards after the restart";
  // it resumed (at least the last checkpoint's updates) rather than starting from zero
  EXPECT_NE(system.Output("learner").find("resumed from"), std::string::npos);
  // actors carried on
  const uint64_t steps = system.nodes["actor-0"].report.steps;
  EXPECT_TRUE(system.WaitUntil([&] { return system.nodes["actor-0"].report.steps > steps; }, 20s));
  EXPECT_TRUE(system.child("actor-0").running());
  EXPECT_TRUE(system.child("actor-1").running());
}

TEST(SystemTest, RestartedGraphServiceRepublishesTheSavedGraphWithoutRetraining) {
  System system("graph-restart", {"run.total_env_steps=1000000"});
  system.StartAll(1);
  ASSERT_TRUE(system.WaitUntil([&] { return system.graph.has_value(); }, 120s)) << system.Output("graph");
  const rl::GraphUpdate first = *system.graph;
  system.child("graph").Signal(SIGTERM);
  ASSERT_TRUE(system.child("graph").WaitFor(5s).has_value());
  const int received = system.graphs_received;
  const auto restarted = std::chrono::steady_clock::now();
  system.Start("graph");
  ASSERT_TRUE(system.WaitUntil([&] { return system.graphs_received > received; }, 20s)) << system.Output("graph");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - restarted).count();
  EXPECT_LT(seconds, 5.0) << "re-publishing took " << seconds << " s: was it retrained?";
  EXPECT_EQ(system.graph->version, first.version);
  EXPECT_EQ(system.graph->graph.adjacency, first.graph.adjacency);
  EXPECT_EQ(system.graph->mean_weights, first.mean_weights);
  EXPECT_EQ(system.graph->training_updates, first.training_updates);
}

TEST(SystemTest, LateActorGetsGraphAndWeightsWithinTwoSeconds) {
  System system("late-actor", {"run.total_env_steps=1000000"});
  system.StartAll(1);
  ASSERT_TRUE(system.WaitUntil([&] { return system.graph && system.latest_weights > 1; }, 180s))
      << system.Output("learner");
  system.Start("actor-5");
  const auto started = std::chrono::steady_clock::now();
  ASSERT_TRUE(system.WaitUntil(
      [&] {
        auto it = system.nodes.find("actor-5");
        return it != system.nodes.end() && it->second.report.graph_version > 0 && it->second.report.policy_version > 0;
      },
      10s))
      << system.Output("actor-5");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  EXPECT_LT(seconds, 2.0) << "a late actor took " << seconds << " s (process start included)";
}

TEST(SystemTest, MalformedEpisodesFromAForeignParticipantAreDroppedAndCounted) {
  System system("foreign", {"run.total_env_steps=1000000"});
  system.StartAll(1);
  ASSERT_TRUE(system.WaitUntil([&] { return system.stats && system.stats->updates > 20; }, 180s))
      << system.Output("learner");
  // a participant of our own, writing what the contract forbids (validation switched off)
  tr::WriterOptions raw;
  raw.validate = false;
  tr::Writer<rl::Episode> foreign(system.participant(), raw);
  rl::Episode bad;
  bad.layout = {3, 3, false};  // 5 floats per entity
  bad.action_dim = 2;
  bad.num_steps = 20;
  bad.entity_kinds = {0, 1, 2};
  bad.states.assign(21 * 3 * 5, 0.1f);
  bad.actions.assign(40, 0.0f);
  bad.states[17] = std::nanf("");
  for (int i = 0; i < 10; ++i) ASSERT_EQ(foreign.Write(bad), tr::WriteResult::kSent);
  bad.states[17] = 0.1f;
  bad.actions.pop_back();  // wrong length
  for (int i = 0; i < 10; ++i) ASSERT_EQ(foreign.Write(bad), tr::WriteResult::kSent);
  const uint64_t updates = system.stats->updates;
  ASSERT_TRUE(system.WaitUntil([&] { return system.nodes["learner-0"].report.dropped >= 20; }, 20s))
      << "learner dropped " << system.nodes["learner-0"].report.dropped;
  EXPECT_TRUE(system.WaitUntil([&] { return system.stats->updates > updates + 20; }, 30s)) << "training stopped";
  EXPECT_TRUE(system.child("learner").running());
  EXPECT_TRUE(system.child("graph").running());
  EXPECT_TRUE(system.child("actor-0").running());
}

}  // namespace
}  // namespace srics::testing

namespace srics::testing {
namespace {

TEST(RoleProcessTest, BadConfigOrCommandLineExitsWith2AndSaysWhat) {
  const std::string dir = ::testing::TempDir() + "/role-bad-config";
  std::filesystem::create_directories(dir);
  const std::string config = SourceDir() + "/tests/integration/system-test.yaml";
  struct Case {
    std::vector<std::string> argv;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {{BinaryDir() + "/learner/srics-learner", config, "--set", "learner.warmup_step=5"},
       "learner.warmup_step: unknown key (did you mean 'warmup_steps'?)"},
      {{BinaryDir() + "/graph_service/srics-graph", config, "--set", "graph.threshold=2"},
       "graph.threshold: expected a number in [0, 1], got '2'"},
      {{BinaryDir() + "/actor/srics-actor", config}, "--id K is required"},
      {{BinaryDir() + "/actor/srics-actor", config, "--id", "x1"}, "--id: expected a non-negative integer"},
  };
  for (const Case& c : cases) {
    launcher::SpawnOptions options;
    options.output_file = dir + "/out.txt";
    std::filesystem::remove(options.output_file);
    auto child = launcher::ChildProcess::Spawn(c.argv, options);
    auto status = child.WaitFor(10s);
    ASSERT_TRUE(status.has_value()) << c.argv[0];
    EXPECT_FALSE(status->signaled);
    EXPECT_EQ(status->code, 2) << c.argv[0];
    std::ifstream in(options.output_file);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_NE(text.find(c.expected), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace srics::testing
