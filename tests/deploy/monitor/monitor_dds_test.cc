// The monitor over real DDS (loopback, one process, two participants): every topic arrives in
// the state and the CSV files; a node whose writer goes away is shown as lost.

#include "deploy/monitor/monitor.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "tests/common/files/test_files.h"
#include "tests/common/transport/test_samples.h"

namespace srics::monitor {
namespace {

namespace fs = std::filesystem;
namespace tr = srics::transport;
using std::chrono::milliseconds;
using ::testing::HasSubstr;

using files::testing::ReadFile;

TEST(MonitorDdsTest, EveryTopicArrivesAndADeadNodeIsLost) {
  config::TransportConfig transport;
  transport.domain_id = 100 + getpid() % 50;
  transport.run_id = "monitor-test-" + std::to_string(getpid());
  transport.liveliness_lease_s = 0.5;
  transport.status_period_s = 0.2;
  const fs::path dir = fs::temp_directory_path() / transport.run_id;
  fs::remove_all(dir);

  tr::Shutdown shutdown;
  tr::Participant system(transport, shutdown);
  tr::Participant watcher(transport, shutdown);
  Monitor monitor(watcher, {.all_runs = false, .weights = true, .csv_dir = dir.string(), .csv_node_statuses = true});
  EXPECT_EQ(monitor.state().lost_after, milliseconds(900));

  std::optional<tr::Writer<rl::NodeStatus>> status_writer(std::in_place, system);
  tr::Writer<rl::LearnerReport> stats_writer(system);
  tr::Writer<rl::EvalReport> eval_writer(system);
  tr::Writer<rl::GraphUpdate> graph_writer(system);
  tr::Writer<rl::WeightsUpdate> weights_writer(system);
  ASSERT_TRUE(stats_writer.WaitForReaders(1, milliseconds(5000)));
  ASSERT_TRUE(eval_writer.WaitForReaders(1, milliseconds(5000)));

  rl::NodeStatus status = tr::testing::MakeNodeStatus(1);
  status.role = "actor";
  status.node_id = 3;
  status.report.phase = rl::NodePhase::kTraining;
  rl::LearnerReport stats = tr::testing::MakeLearnerStats(2);
  stats.updates = 777;
  rl::EvalReport eval = tr::testing::MakeEvalResult(3);
  eval.policy_version = 9;
  rl::GraphUpdate graph = tr::testing::MakeInteractionGraph(4);
  rl::WeightsUpdate weights = tr::testing::MakePolicyWeights(5, 1000);
  ASSERT_EQ(status_writer->Write(status), tr::WriteResult::kSent);
  ASSERT_EQ(stats_writer.Write(stats), tr::WriteResult::kSent);
  ASSERT_EQ(eval_writer.Write(eval), tr::WriteResult::kSent);
  ASSERT_EQ(graph_writer.Write(graph), tr::WriteResult::kSent);
  ASSERT_EQ(weights_writer.Write(weights), tr::WriteResult::kSent);

  // everything arrives (the node keeps reporting meanwhile, as a live node does)
  const auto deadline = Clock::now() + milliseconds(10000);
  auto complete = [&] {
    const auto it = monitor.state().runs.find(transport.run_id);
    return it != monitor.state().runs.end() && it->second.learner && !it->second.evals.empty() && it->second.graph &&
           it->second.weights && !monitor.state().nodes.empty();
  };
  while (!complete() && Clock::now() < deadline) {
    monitor.Poll(milliseconds(100));
    ASSERT_EQ(status_writer->Write(status), tr::WriteResult::kSent);
  }
  ASSERT_TRUE(complete());
  const RunView& run = monitor.state().runs.at(transport.run_id);
  EXPECT_EQ(run.learner->updates, 777u);
  EXPECT_EQ(run.evals.back().policy_version, 9u);
  EXPECT_EQ(run.graph->version, graph.version);
  EXPECT_EQ(run.weights->version, weights.version);
  EXPECT_EQ(run.weights->num_parameters, 1000u);
  const NodeEntry& node = monitor.state().nodes.at({transport.run_id, "actor", 3});
  EXPECT_EQ(HealthOf(monitor.state(), node, Clock::now()), NodeHealth::kAlive);

  // the node's writer goes away without a goodbye: lost after lease + two periods
  status_writer.reset();
  std::vector<std::string> events;
  const auto lost_deadline = Clock::now() + milliseconds(5000);
  while (events.empty() && Clock::now() < lost_deadline) {
    monitor.Poll(milliseconds(100));
    events = monitor.TakeNodeEvents();
  }
  ASSERT_EQ(events.size(), 1u);
  EXPECT_THAT(events[0], HasSubstr("actor 3"));
  EXPECT_THAT(events[0], HasSubstr("LOST"));

  // the CSV files hold what arrived
  EXPECT_THAT(ReadFile(dir / "learner.csv"), HasSubstr("," + transport.run_id + ",777,"));
  EXPECT_THAT(ReadFile(dir / "eval.csv"),
              HasSubstr("," + transport.run_id + "," + std::to_string(eval.actor_id) + ",9,"));
  EXPECT_THAT(ReadFile(dir / "nodes.csv"), HasSubstr(",actor,3,"));
  EXPECT_THAT(ReadFile(dir / "nodes.csv"), HasSubstr(",lost,"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace srics::monitor
