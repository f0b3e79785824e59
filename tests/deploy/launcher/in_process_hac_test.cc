// `srics run --in-process` with run.method=hac: both levels train on the same loops as every
// method, the evaluation follows the common protocol (eval.csv with the usual columns, finite
// values), and the checkpoint holds the high level beside the low one (so it is not another
// method's pipeline under HAC's name).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/nn/serialize.h"
#include "deploy/launcher/in_process_run.h"

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;

std::vector<std::vector<std::string>> ReadCsv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

size_t Column(const std::vector<std::string>& header, const std::string& name) {
  return static_cast<size_t>(std::find(header.begin(), header.end(), name) - header.begin());
}

TEST(InProcessHacTest, TrainsBothLevelsAndEvaluatesOnTheFullGoal) {
  const std::string dir = ::testing::TempDir() + "/in_process_hac";
  fs::remove_all(dir);
  LaunchOptions options;
  options.config_file = std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml";
  options.overrides = {"run.method=hac",
                       "run.total_env_steps=1500",
                       "learner.warmup_steps=300",
                       "agent.sac.batch_size=32",
                       "learner.publish_every_updates=20",
                       "learner.checkpoint_every_updates=300",
                       "actors.count=2",
                       "actors.eval_every_env_steps=500",
                       "actors.eval_episodes=2",
                       "agent.hac.horizon=5",
                       "run.max_wall_minutes=0"};
  options.run_dir = dir;
  options.display = DisplayMode::kNone;
  options.in_process = true;
  ASSERT_EQ(launcher::Run(options), kExitDone);

  const auto eval = ReadCsv(dir + "/eval.csv");
  ASSERT_GE(eval.size(), 4u) << "a header, the passive baseline and at least two evaluations";
  const auto& header = eval[0];
  for (const char* name : {"env_steps", "policy_version", "avg_distance", "avg_object_distance", "success_rate"})
    ASSERT_LT(Column(header, name), header.size()) << name;
  for (size_t r = 1; r < eval.size(); ++r) {
    ASSERT_EQ(eval[r].size(), header.size());
    for (const char* name : {"avg_distance", "avg_object_distance"}) {
      const double v = std::stod(eval[r][Column(header, name)]);
      EXPECT_TRUE(std::isfinite(v) && v >= 0 && v < 1) << name << " row " << r << ": " << v;
    }
  }
  EXPECT_GE(std::stoi(eval.back()[Column(header, "env_steps")]), 1500);  // episodes vary in length
  EXPECT_NE(eval.back()[Column(header, "policy_version")], "0");

  // the learner trained (updates, finite losses) and checkpointed both levels
  const auto stats = ReadCsv(dir + "/learner.csv");
  ASSERT_GE(stats.size(), 2u);
  EXPECT_GT(std::stod(stats.back()[Column(stats[0], "updates")]), 100);
  EXPECT_TRUE(std::isfinite(std::stod(stats.back()[Column(stats[0], "q_loss")])));
  const auto sections = nn::ReadCheckpoint(dir + "/checkpoint.srics");
  bool high = false, low = false;
  for (const auto& s : sections) {
    high = high || s.name == "hac.high.policy";
    low = low || s.name == "policy";
  }
  EXPECT_TRUE(high && low);
}

}  // namespace
}  // namespace srics::launcher
