// The analysis library: statistics against hand-computed values, and the two evaluation
// studies' rows and tables made again from the committed raw evaluations of the campaign
// (docs/results/campaign/cross-eval and seen-unseen, written by the shell scripts these
// functions replace): the same CSV rows and the same tables but for the line that names the writer.
#include "deploy/analysis/eval_studies.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <sstream>
#include <utility>

#include "deploy/analysis/statistics.h"
#include "deploy/run_folder/csv.h"
#include "tests/common/files/test_files.h"

namespace srics::analysis {
namespace {

namespace fs = std::filesystem;
using files::testing::ReadFile;

const fs::path kCampaign = fs::path(SRICS_SOURCE_DIR) / "docs/results/campaign";

TEST(StatisticsTest, MeanSampleSdAndPairedDifferences) {
  const Spread s = SpreadOf({0.10, 0.14, 0.18});
  EXPECT_DOUBLE_EQ(s.mean, 0.14);
  EXPECT_NEAR(s.std, 0.04, 1e-12);  // sqrt((0.0016 + 0 + 0.0016) / 2)
  EXPECT_DOUBLE_EQ(s.min, 0.10);
  EXPECT_DOUBLE_EQ(s.max, 0.18);
  EXPECT_EQ(s.n, 3);
  EXPECT_EQ(SpreadOf({0.3}).std, 0.0);
  EXPECT_EQ(SpreadOf({}).n, 0);
  EXPECT_EQ(Differences({1, 2}, {1.5, 1}), (std::vector<double>{0.5, -1}));
  EXPECT_THROW(Differences({1}, {1, 2}), std::invalid_argument);
  EXPECT_EQ(Format(0.12345), "0.123");
  EXPECT_EQ(Format(0.5, 2), "0.50");
  EXPECT_EQ(Format(0.01, 3, /*sign=*/true), "+0.010");
  EXPECT_EQ(MeanStd(SpreadOf({-0.01, -0.03}), 3, /*sign=*/true), "-0.020 ± 0.014");
  EXPECT_EQ(MeanStd(SpreadOf({})), "-");
}

// The table as the scripts wrote it, without the sentence that names its writer.
std::string WithoutWriter(const std::string& table) {
  return std::regex_replace(table, std::regex(" Written by [^\n]*\\.\n"), "\n");
}

// Each row of a committed study's CSV after its header (which must be `header`), with its fields.
std::vector<std::pair<std::string, std::vector<std::string>>> StudyRows(const std::string& csv,
                                                                        const std::string& header) {
  std::istringstream in(csv);
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, header);
  std::vector<std::pair<std::string, std::vector<std::string>>> rows;
  for (std::string line; std::getline(in, line);) rows.emplace_back(line, run_folder::SplitCsvLine(line));
  EXPECT_FALSE(rows.empty()) << "a study without rows";
  return rows;
}

TEST(CrossEvalTest, RowsAndTableOfTheCommittedStudyComeOutTheSame) {
  const fs::path study = kCampaign / "cross-eval";
  const std::string csv = ReadFile(study / "cross-eval.csv");
  for (const auto& [row, fields] : StudyRows(csv, kCrossEvalHeader)) {
    ASSERT_GE(fields.size(), 4u) << row;
    const std::string &run = fields[0], &method = fields[1], &protocol = fields[2], &goal_set = fields[3];
    const fs::path raw = study / "raw";
    const std::set<int> objects = AttemptedObjects(raw / (run + "-depth-goals" + goal_set));
    EXPECT_EQ(CrossEvalRow(run, method, protocol, std::stoull(goal_set),
                           raw / (run + "-" + protocol + "-goals" + goal_set), objects),
              row);
  }
  EXPECT_EQ(WithoutWriter(CrossEvalTable(csv, "1 2 3", 20)), WithoutWriter(ReadFile(study / "cross-eval.md")));
}

TEST(SeenUnseenTest, RowsAndTableOfTheCommittedStudyComeOutTheSame) {
  const fs::path study = kCampaign / "seen-unseen";
  const std::string csv = ReadFile(study / "seen-unseen.csv");
  for (const auto& [row, fields] : StudyRows(csv, kSeenUnseenHeader)) {
    ASSERT_GE(fields.size(), 3u) << row;
    const std::string &run = fields[0], &combination = fields[1], &kind = fields[2];
    std::string tag = run + "-objects" + combination;
    for (char& c : tag) c = c == ' ' ? '-' : c;
    EXPECT_EQ(SeenUnseenRow(run, combination, kind, study / "raw" / (tag + "-policy") / "episodes.csv",
                            study / "raw" / (tag + "-passive") / "episodes.csv"),
              row);
  }
  EXPECT_EQ(WithoutWriter(SeenUnseenTable(csv, "1,2,3 1,2,4 1,3,4", "2,3,4", 50)),
            WithoutWriter(ReadFile(study / "seen-unseen.md")));
}

TEST(EvalStudiesTest, ATableOfACsvWithoutItsColumnsIsRefusedNamingTheColumn) {
  try {
    CrossEvalTable("run,method\nsrics-seed1,srics\n", "1", 20);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no column protocol"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SeenUnseenTable("", "1,2", "3", 5), std::invalid_argument);
  // no episodes: the row says 0 and leaves the means empty
  EXPECT_EQ(ObjectDistanceOf("/nonexistent/episodes.csv"), "0,");
}

}  // namespace
}  // namespace srics::analysis
