// A run with a given graph: SeedGraphFile writes it into the run folder as graph.json, which
// the graph service then re-publishes instead of learning.

#include "deploy/launcher/run_folder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "common/rl/ground_truth.h"
#include "graph_service/learned_graph.h"

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;

config::Config Load(const std::string& name, std::vector<std::string> overrides) {
  return config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/" + name, overrides);
}

std::string FreshDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(SeedGraphFileTest, GroundTruthIsAValidGraphFileWithTheConfigsEdges) {
  const std::string dir = FreshDir("seed_ground_truth");
  const config::Config config = Load("relational-4.yaml", {"graph.ground_truth=true"});
  SeedGraphFile(config, dir);
  // the graph service loads it (LoadGraph validates everything a saved graph must hold)
  const auto loaded = graph_service::LoadGraph(dir + "/graph.json");
  EXPECT_EQ(loaded.graph.adjacency, rl::GroundTruthGraph(config.env).adjacency);
  EXPECT_EQ(rl::DescribeGraph(loaded.graph), "action->0, 0->2, 0->3, 0->4, 2->3, 3->2");
  EXPECT_EQ(loaded.version, 1u);
}

TEST(SeedGraphFileTest, AGivenFileIsCopiedAndAnExistingGraphIsKept) {
  const std::string source = FreshDir("seed_source");
  SeedGraphFile(Load("rearrange-3.yaml", {"graph.ground_truth=true"}), source);
  const std::string dir = FreshDir("seed_file");
  SeedGraphFile(Load("rearrange-3.yaml", {"graph.file=" + source + "/graph.json"}), dir);
  EXPECT_EQ(graph_service::LoadGraph(dir + "/graph.json").mean_weights, graph_service::LoadGraph(source + "/graph.json").mean_weights);
  // a continued run keeps its own graph
  const auto before = fs::last_write_time(dir + "/graph.json");
  SeedGraphFile(Load("rearrange-3.yaml", {"graph.ground_truth=true"}), dir);
  EXPECT_EQ(fs::last_write_time(dir + "/graph.json"), before);
}

TEST(SeedGraphFileTest, BadInputIsNamed) {
  const std::string dir = FreshDir("seed_bad");
  std::ofstream(dir + "/broken.json") << "{\"format\": \"srics-interaction-graph\"";
  EXPECT_THROW(SeedGraphFile(Load("rearrange-3.yaml", {"graph.file=" + dir + "/broken.json"}), dir + "/run"),
               std::runtime_error);
  EXPECT_THROW(SeedGraphFile(Load("rearrange-3.yaml", {"graph.ground_truth=true"}), ""), std::runtime_error);
  // nothing to do without a given graph
  SeedGraphFile(Load("rearrange-3.yaml", {}), dir);
  EXPECT_FALSE(fs::exists(dir + "/graph.json"));
}

// Issue 15: run ids unique per launch, kept by a resumed run.
TEST(RunIdTest, EveryLaunchGetsItsOwnAndAFolderKeepsTheOneItRecorded) {
  const std::string a = NewRunId(), b = NewRunId();
  EXPECT_NE(a, b);
  EXPECT_LE(a.size(), 64u);
  EXPECT_NE(a.find("-" + std::to_string(getpid()) + "-"), std::string::npos) << a;
  const std::string dir = ::testing::TempDir() + "/run_id_test_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  EXPECT_NE(ChooseRunId(dir), ChooseRunId(dir)) << "no folder yet: a new id each time";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/config.yaml") << "# effective configuration\ntransport:\n  run_id: earlier-launch\n";
  EXPECT_EQ(ChooseRunId(dir), "earlier-launch");
  std::ofstream(dir + "/config.yaml") << "transport:\n  run_id: auto\n";
  EXPECT_NE(ChooseRunId(dir), "auto");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace srics::launcher
