#include "deploy/monitor/csv_sink.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/deploy/monitor/test_states.h"

namespace srics::monitor {
namespace {

namespace fs = std::filesystem;
using testing::Eval;
using testing::Node;

std::vector<std::string> Lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class CsvSinkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = (fs::temp_directory_path() / ("srics_csv_test_" + std::to_string(getpid()))).string();
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string dir_;
};

TEST_F(CsvSinkTest, WritesHeadersAndRows) {
  CsvSink sink(dir_ + "/sub");  // created
  rl::EvalReport eval_result = Eval(42, 50000, 0.125f);
  eval_result.summary.independent_solved = 7;  // the compatibility counts end the row
  eval_result.summary.independent_undone = 2;
  sink.Append("r1", eval_result, 1700000000.5);
  rl::LearnerReport stats;
  stats.updates = 99;
  stats.transitions_inserted = 1000;
  stats.q_loss = 0.5f;
  sink.Append("r1", stats, 1700000001.0);
  sink.Append("r1", Node("actor", 3, rl::NodePhase::kTraining), 1700000002.0);

  const auto eval = Lines(dir_ + "/sub/eval.csv");
  ASSERT_EQ(eval.size(), 2u);
  EXPECT_EQ(eval[0].rfind("wall_time,run_id,actor_id,policy_version,", 0), 0u);
  EXPECT_NE(eval[0].find(",subgoal_success,independent_solved,independent_undone"), std::string::npos) << eval[0];
  EXPECT_EQ(eval[1], "1700000000.500,r1,0,42,1,50000,20,0.135,0.125,0.5,0.75,0.01;0.1;0.2,1;0.8;0.25,7,2");

  const auto learner = Lines(dir_ + "/sub/learner.csv");
  ASSERT_EQ(learner.size(), 2u);
  EXPECT_EQ(learner[1].rfind("1700000001.000,r1,99,1000,0,0,0,0,0.5,", 0), 0u);

  const auto nodes = Lines(dir_ + "/sub/nodes.csv");
  ASSERT_EQ(nodes.size(), 2u);
  EXPECT_EQ(nodes[1], "1700000002.000,r1,actor,3,host-actor,1003,training,7,1,12345,0,61000,");
}

TEST_F(CsvSinkTest, ReopeningAppendsWithoutASecondHeader) {
  {
    CsvSink sink(dir_);
    sink.Append("r1", Eval(1, 10, 0.3f), 1.0);
  }
  {
    CsvSink sink(dir_);
    sink.Append("r1", Eval(2, 20, 0.2f), 2.0);
  }
  const auto eval = Lines(dir_ + "/eval.csv");
  ASSERT_EQ(eval.size(), 3u);
  EXPECT_EQ(eval[1].substr(0, 12), "1.000,r1,0,1");
  EXPECT_EQ(eval[2].substr(0, 12), "2.000,r1,0,2");
}

TEST_F(CsvSinkTest, QuotesDetailAndMarksLostNodes) {
  CsvSink sink(dir_);
  rl::NodeStatus status = Node("learner", 0, rl::NodePhase::kTraining);
  status.report.detail = "waiting, for \"graph\"";
  sink.Append("r1", status, 5.0, "lost");
  const auto nodes = Lines(dir_ + "/nodes.csv");
  ASSERT_EQ(nodes.size(), 2u);
  EXPECT_THAT(nodes[1], ::testing::HasSubstr(",lost,"));
  EXPECT_THAT(nodes[1], ::testing::EndsWith(",\"waiting, for \"\"graph\"\"\""));
}

TEST(CsvFieldTest, QuotesOnlyWhenNeeded) {
  EXPECT_EQ(CsvField("plain"), "plain");
  EXPECT_EQ(CsvField("a,b"), "\"a,b\"");
  EXPECT_EQ(CsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  // peers' strings: control characters (a line break, an escape) are not written (issue 15)
  EXPECT_EQ(CsvField("two\nlines"), "two?lines");
  EXPECT_EQ(CsvField("\x1b[2J,x"), "\"?[2J,x\"");
}

TEST(CsvSinkErrorTest, UnwritableFolderNamesThePath) {
  try {
    CsvSink sink("/proc/srics-no-such-dir/x");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("/proc/srics-no-such-dir/x"));
  }
}

}  // namespace
}  // namespace srics::monitor
