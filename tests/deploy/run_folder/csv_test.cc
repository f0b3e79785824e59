// The run folder's one CSV reader and writer: fields, quoting, rows by name, files still being
// written, and the headers the monitor's sink writes.
#include "deploy/run_folder/csv.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "deploy/run_folder/schema.h"

namespace srics::run_folder {
namespace {

namespace fs = std::filesystem;

TEST(SplitCsvLineTest, SplitsOnCommasOutsideQuotesAndUndoublesQuotes) {
  EXPECT_EQ(SplitCsvLine("a,b,,c"), (std::vector<std::string>{"a", "b", "", "c"}));
  EXPECT_EQ(SplitCsvLine("\"x,y\",\"say \"\"hi\"\"\",3"), (std::vector<std::string>{"x,y", "say \"hi\"", "3"}));
  EXPECT_EQ(SplitCsvLine(""), (std::vector<std::string>{""}));
  EXPECT_EQ(SplitCsvLine("0.1;0.2,7"), (std::vector<std::string>{"0.1;0.2", "7"}));
}

TEST(QuoteCsvFieldTest, QuotesOnlyWhenNeededAndSplitsBackToTheText) {
  EXPECT_EQ(QuoteCsvField("plain"), "plain");
  EXPECT_EQ(QuoteCsvField("a,b"), "\"a,b\"");
  EXPECT_EQ(QuoteCsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  for (const std::string& text : std::vector<std::string>{"plain", "a,b", "say \"hi\"", ",\"\",", ""})
    EXPECT_EQ(SplitCsvLine(QuoteCsvField(text) + "," + QuoteCsvField(text)), (std::vector<std::string>{text, text}));
}

TEST(JoinedValuesTest, JoinsWithSemicolonsAndSplitsBack) {
  EXPECT_EQ(JoinedValues(std::vector<float>{0.5f, 0.25f, 1.0f}), "0.5;0.25;1");
  EXPECT_EQ(JoinedValues(std::vector<float>{}), "");
  // doubles (attempts.csv's distances) with the same precision: 6 significant digits
  EXPECT_EQ(JoinedValues(std::vector<double>{0.123456789, 2.0}), "0.123457;2");
  EXPECT_EQ(SplitValues("0.5;0.25;1"), (std::vector<double>{0.5, 0.25, 1.0}));
  EXPECT_EQ(SplitValues("0.5;;2"), (std::vector<double>{0.5, 2.0}));
}

TEST(CsvTableTest, ReadsRowsByColumnNameLenientlyOrStrictly) {
  const auto table = CsvTable::Parse("a,b,list\n1,x,0.1;0.2\n-2,,oops\n7\n");
  ASSERT_TRUE(table);
  ASSERT_EQ(table->size(), 3u);
  EXPECT_EQ(table->header(), (std::vector<std::string>{"a", "b", "list"}));
  const CsvRow first = table->Row(0), second = table->Row(1), short_row = table->Row(2);
  EXPECT_EQ(first.Number("a"), 1.0);
  EXPECT_EQ(first.Text("b"), "x");
  EXPECT_EQ(first.Unsigned("a"), 1u);
  EXPECT_EQ(first.Floats("list"), (std::vector<float>{0.1f, 0.2f}));
  EXPECT_FALSE(first.Number("b"));        // not a number
  EXPECT_FALSE(first.Number("missing"));  // no such column
  EXPECT_EQ(first.Text("missing"), "");
  EXPECT_FALSE(second.Number("b"));  // empty
  EXPECT_EQ(second.Double("a"), -2.0);
  EXPECT_THROW(second.Unsigned("a"), std::invalid_argument);  // negative: not a count
  EXPECT_THROW(second.Double("b"), std::invalid_argument);    // empty
  EXPECT_THROW(second.Floats("list"), std::invalid_argument);
  EXPECT_THROW(first.TextOrThrow("missing"), std::invalid_argument);
  EXPECT_TRUE(short_row.Has("a"));
  EXPECT_FALSE(short_row.Has("b"));  // the row ends before it
  EXPECT_THROW(short_row.TextOrThrow("b"), std::invalid_argument);
  int seen = 0;
  for (const CsvRow& row : table->Rows()) seen += row.Text("a").empty() ? 0 : 1;
  EXPECT_EQ(seen, 3);
}

TEST(CsvTableTest, LeavesOutTheUnfinishedLastLineOfAFileStillBeingWritten) {
  EXPECT_EQ(CsvTable::Parse("a\n1\n2")->size(), 2u);
  EXPECT_EQ(CsvTable::Parse("a\n1\n2", /*complete_lines_only=*/true)->size(), 1u);
  EXPECT_EQ(CsvTable::Parse("a\n1\n2\n", /*complete_lines_only=*/true)->size(), 2u);
  EXPECT_FALSE(CsvTable::Parse(""));  // no header
  EXPECT_FALSE(CsvTable::Read("/nonexistent/eval.csv"));
}

TEST(ForEachRowTest, CountsTheRowsItsParserRefusesAndGoesOn) {
  const fs::path path = fs::path(::testing::TempDir()) / "for_each_row.csv";
  std::ofstream(path) << "n\n1\nx\n3\n4";  // "x" refused; "4" unfinished
  std::vector<uint64_t> values;
  uint64_t skipped = 0;
  ForEachRow(
      path, [&](const CsvRow& row) { values.push_back(row.Unsigned("n")); }, &skipped);
  EXPECT_EQ(values, (std::vector<uint64_t>{1, 3}));
  EXPECT_EQ(skipped, 1u);
  ForEachRow(
      "/nonexistent.csv", [&](const CsvRow&) { FAIL(); }, &skipped);
}

// The header lines as the files had them before the schema (2026-12-04 and since): a reordered
// or renamed column here would break every reader of older run folders.
TEST(SchemaTest, HeadersAreTheLinesTheFilesAlwaysHad) {
  EXPECT_EQ(HeaderLine(kEvalColumns),
            "wall_time,run_id,actor_id,policy_version,graph_version,env_steps,episodes,avg_distance,"
            "avg_object_distance,success_rate,selectivity,entity_distance,subgoal_success,independent_solved,"
            "independent_undone");
  EXPECT_EQ(HeaderLine(kLearnerColumns),
            "wall_time,run_id,updates,transitions_inserted,replay_size,episodes_accepted,episodes_rejected,"
            "policy_version,q_loss,policy_loss,alpha,entropy,updates_per_second,inserts_per_second,mean_reward");
  EXPECT_EQ(HeaderLine(kNodesColumns),
            "wall_time,run_id,role,node_id,host,pid,state,policy_version,graph_version,env_steps,dropped_samples,"
            "uptime_ms,detail");
  EXPECT_EQ(HeaderLine(kEpisodesLeadingColumns),
            "episode,seed,status,steps,frames,avg_distance,avg_object_distance,success,selectivity,independent_solved,"
            "independent_undone");
  EXPECT_EQ(HeaderLine(kAttemptsColumns),
            "episode,attempt,entity,skipped,distance_before,distance_after,reached,others_solved,others_undone,"
            "independent_solved,independent_undone,distances_before,distances_after,others_undone_before_moved");
  EXPECT_EQ(HeaderLine({"a", "b"}), "a,b");
  // the committed campaign's files read by name through these columns
  const auto eval =
      CsvTable::Read(fs::path(SRICS_SOURCE_DIR) / "docs/results/campaign/raw/relational-4-750k/srics-seed1/eval.csv");
  ASSERT_TRUE(eval);
  EXPECT_EQ(eval->header(), kEvalColumns);
}

TEST(CsvTableTest, BlankLinesAreNoRows) {
  EXPECT_EQ(CsvTable::Parse("a\n1\n\n2\n")->size(), 2u);
  const fs::path path = fs::path(::testing::TempDir()) / "blank_lines.csv";
  std::ofstream(path) << "n\n1\n\n2\n";
  uint64_t skipped = 0;
  int rows = 0;
  ForEachRow(
      path, [&](const CsvRow&) { ++rows; }, &skipped);
  EXPECT_EQ(rows, 2);
  EXPECT_EQ(skipped, 0u);
}

}  // namespace
}  // namespace srics::run_folder
