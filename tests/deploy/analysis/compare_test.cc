// `srics compare` on hand-made run folders: the final figures are each run's last evaluation
// (never its best), summarized as mean ± sample std over seeds; curves are the mean over seeds
// with a band of ±1 sample sd (or min-max); the figures are PNG files.

#include "deploy/analysis/compare.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "common/graph_file/graph_file.h"
#include "deploy/run_folder/outcome.h"
#include "tests/common/files/test_files.h"

namespace srics::analysis {
namespace {

namespace fs = std::filesystem;
using files::testing::ReadFile;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr const char* kEvalHeader =
    "wall_time,run_id,actor_id,policy_version,graph_version,env_steps,episodes,avg_distance,avg_object_distance,"
    "success_rate,selectivity,entity_distance,subgoal_success\n";

// one eval.csv row: version, env steps, avg distance, avg object distance, success per subgoal
std::string Row(int version, int steps, double distance, double object, const std::string& subgoals) {
  std::ostringstream row;
  row << "1.0,r,0," << version << ",1," << steps << ",5," << distance << ',' << object << ",0.5,0.4,0.1;0.1,"
      << subgoals << "\n";
  return row.str();
}

class CompareTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sweep_ = root_ / "sweep";
    fs::create_directories(sweep_);
    std::ofstream(sweep_ / "sweep.yaml")
        << "# a sweep\nconfig: \"/somewhere/relational-4.yaml\"\nmethods: [smorl, srics]\n";
    // srics seed 1: its best evaluation (0.05) is not its last (0.10)
    Write("srics-seed1",
          Row(0, 0, 0.30, 0.28, "0;0") + Row(3, 1000, 0.05, 0.04, "1;0.2") + Row(6, 2000, 0.10, 0.08, "1;0.4"),
          "wall_time,env_steps,episodes,selectivity,selectivity_episodes,subgoal_distance,subgoal_success\n"
          "1,1000,10,0.5,10,0.1,0.2\n1,2000,10,0.7,10,0.1,0.2\n");
    // srics seed 2: two evaluators at the final step count (averaged: 0.14)
    Write("srics-seed2",
          Row(0, 0, 0.32, 0.30, "0;0") + Row(3, 1000, 0.20, 0.18, "1;0") + Row(6, 2000, 0.13, 0.10, "0.5;0.6") +
              Row(6, 2000, 0.15, 0.12, "1;0.6"),
          "wall_time,env_steps,episodes,selectivity,selectivity_episodes,subgoal_distance,subgoal_success\n"
          "1,1000,10,0.3,10,0.1,0.2\n1,2000,10,0.5,10,0.1,0.2\n");
    run_folder::WriteRunOutcome((sweep_ / "srics-seed2").string(), {"finished", 0, "the budget is done"});
    // smorl seed 1 logs the selectivity with the table's graph too (0.8, against its own 0.3)
    Write("smorl-seed1",
          Row(0, 0, 0.31, 0.29, "0;0") + Row(2, 1000, 0.25, 0.20, "1;0") + Row(4, 2000, 0.20, 0.18, "1;0"),
          "wall_time,env_steps,episodes,selectivity,selectivity_episodes,subgoal_distance,subgoal_success,"
          "table_graph_selectivity,table_graph_selectivity_episodes\n"
          "1,1000,10,0.2,10,0.1,0.2,0.7,10\n1,2000,10,0.3,10,0.1,0.2,0.8,10\n");
  }

  // `srics compare` of the sweep folder into `out`: its exit code.
  int CompareSweepInto(const fs::path& out) const {
    CompareOptions options;
    options.dirs = {sweep_.string()};
    options.out_dir = out.string();
    return Compare(options);
  }

  void Write(const std::string& run, const std::string& eval_rows, const std::string& train) {
    fs::create_directories(sweep_ / run);
    std::ofstream(sweep_ / run / "eval.csv") << kEvalHeader << eval_rows;
    if (!train.empty()) std::ofstream(sweep_ / run / "train.csv") << train;
  }

  files::testing::ScratchFolder root_{"srics_compare_test"};
  fs::path sweep_;
};

TEST(CompareMathTest, SpreadIsMeanSampleStdMinMax) {
  const Spread s = SpreadOf({0.10, 0.14});
  EXPECT_DOUBLE_EQ(s.mean, 0.12);
  EXPECT_NEAR(s.std, 0.028284271, 1e-8);  // sqrt(2 * 0.02^2 / 1)
  EXPECT_DOUBLE_EQ(s.min, 0.10);
  EXPECT_DOUBLE_EQ(s.max, 0.14);
  EXPECT_EQ(s.n, 2);
  EXPECT_EQ(SpreadOf({0.3}).std, 0.0);
  EXPECT_EQ(SpreadOf({}).n, 0);
}

TEST(CompareMathTest, InterpolatesInsideTheCurveOnly) {
  const std::vector<std::pair<double, double>> c = {{1000, 0.2}, {2000, 0.1}};
  EXPECT_NEAR(*Interpolate(c, 1500), 0.15, 1e-12);
  EXPECT_EQ(*Interpolate(c, 2000), 0.1);
  EXPECT_FALSE(Interpolate(c, 999));
  EXPECT_FALSE(Interpolate(c, 2001));
}

TEST_F(CompareTest, ReadsRunsByMethodSeedAndEnvironment) {
  std::vector<std::string> warnings;
  const std::vector<RunData> runs = ReadRuns({sweep_.string()}, &warnings);
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(runs[0].method, "smorl");
  EXPECT_EQ(runs[1].method, "srics");
  EXPECT_EQ(runs[2].seed, 2u);
  EXPECT_EQ(runs[0].environment, "relational-4");
  EXPECT_FALSE(runs[1].finished);
  EXPECT_TRUE(runs[2].finished);
  ASSERT_TRUE(runs[1].passive);
  EXPECT_DOUBLE_EQ(runs[1].passive->avg_distance, 0.30);
  ASSERT_EQ(runs[2].evaluations.size(), 2u);
  EXPECT_NEAR(runs[2].evaluations.back().avg_distance, 0.14, 1e-12);
  EXPECT_EQ(runs[2].evaluations.back().subgoal_success, (std::vector<double>{0.75, 0.6}));
  EXPECT_EQ(runs[1].selectivity.back(), (std::pair<double, double>{2000, 0.7}));
  EXPECT_FALSE(runs[1].selectivity_with_table_graph);
  EXPECT_EQ(runs[0].selectivity.back(), (std::pair<double, double>{2000, 0.8}));
  EXPECT_TRUE(runs[0].selectivity_with_table_graph);
}

// A method whose runs logged different selectivity measures (a run from before the table-graph
// column beside one with it) shows only the table-graph ones: the measures never mix.
TEST_F(CompareTest, SelectivityMeasuresNeverMixWithinAMethod) {
  Write("smorl-seed3", Row(0, 0, 0.31, 0.29, "0;0") + Row(4, 2000, 0.22, 0.19, "1;0"),
        "wall_time,env_steps,episodes,selectivity,selectivity_episodes,subgoal_distance,subgoal_success\n"
        "1,2000,10,0.25,10,0.1,0.2\n");
  std::vector<std::string> warnings;
  const std::vector<RunData> runs = ReadRuns({sweep_.string()}, &warnings);
  ASSERT_EQ(runs.size(), 4u);
  EXPECT_EQ(runs[1].method, "smorl");
  EXPECT_EQ(runs[1].seed, 3u);
  EXPECT_TRUE(runs[1].selectivity.empty()) << "its own-ancestor measure is left out beside seed 1's";
  EXPECT_EQ(runs[0].selectivity.back().second, 0.8);
  const std::string table = FinalTable(runs);
  EXPECT_THAT(table, HasSubstr("| 0.800 ± 0.000 | 0.310 ± 0.000 |")) << table;
  // srics has only own-ancestor measures: shown, marked
  EXPECT_THAT(table, HasSubstr("| 0.500 ± 0.000 * |")) << table;
  // the selectivity figure's legend counts the runs that draw in it: smorl 1 of its 2
  ASSERT_EQ(CompareSweepInto(root_ / "out"), 0);
  const std::string script = ReadFile(root_ / "out" / "relational-4.gnuplot");
  const size_t selectivity = script.find("relational-4-selectivity.png");
  ASSERT_NE(selectivity, std::string::npos) << script;
  EXPECT_NE(script.find("title 'smorl (1 seed)'", selectivity), std::string::npos) << script;
  EXPECT_NE(script.find("title 'smorl (2 seeds)'"), std::string::npos) << "the distance figures count both";
}

TEST_F(CompareTest, TableHoldsFinalValuesAsMeanAndStdOverSeeds) {
  std::vector<std::string> warnings;
  const std::string table = FinalTable(ReadRuns({sweep_.string()}, &warnings));
  // srics: seed 2 finished, seed 1 did not: only seed 2's last evaluation counts (two evaluators
  // averaged: 0.14, objects 0.11; never a best one), not the unfinished run's 0.10
  EXPECT_THAT(table, HasSubstr("## relational-4"));
  EXPECT_THAT(table, HasSubstr("| srics | 1 | 1/2 | 2000 | 0.140 ± 0.000 | 0.110 ± 0.000 | 0.50 ± 0.00 | "
                               "0.75 ± 0.00 | 0.60 ± 0.00 | 0.500 ± 0.000 * | 0.320 ± 0.000 | 0.37 ± 0.00 |"))
      << table;
  // smorl has no finished run: its unfinished one's last evaluation is shown
  EXPECT_THAT(table, HasSubstr("| smorl | 1 | 0/1 | 2000 | 0.200 ± 0.000 | 0.180 ± 0.000 |")) << table;
  // its selectivity measured with the table's graph: no mark
  EXPECT_THAT(table, HasSubstr("| 0.800 ± 0.000 | 0.310 ± 0.000 |")) << table;
  EXPECT_THAT(table, HasSubstr("srics-seed1 (not finished)"));
}

// The unseen combination's runs evaluate the held-out pucks 2-4 (env.eval_object_sets): the
// table and the subgoal bars name each object by its catalogue number, not its place in the
// episode ("object 1" was puck 2); runs of one environment that play different sets keep
// the episode's numbering.
TEST_F(CompareTest, NamesHeldOutObjectsByTheirCatalogueNumber) {
  const std::string held_out =
      "env:\n  num_pucks: 4\n  object_sets:\n    - {present: [1, 2, 3]}\n    - {present: [1, 2, 4]}\n"
      "  eval_object_sets:\n    - {present: [3, 4]}\n";
  for (const char* run : {"srics-seed1", "srics-seed2", "smorl-seed1"})
    std::ofstream(sweep_ / run / "config.yaml") << held_out;
  std::vector<std::string> warnings;
  std::vector<RunData> runs = ReadRuns({sweep_.string()}, &warnings);
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[1].eval_objects, (std::vector<int>{3, 4}));
  EXPECT_THAT(FinalTable(runs), HasSubstr("| success arm | success object 3 | training selectivity |"));
  ASSERT_EQ(CompareSweepInto(root_ / "out"), 0);
  EXPECT_THAT(ReadFile(root_ / "out" / "relational-4-subgoal_success.dat"), HasSubstr("\n\"object 3\""));

  runs[0].eval_objects = {2, 4};  // another set in the same environment
  EXPECT_THAT(FinalTable(runs), HasSubstr("| success arm | success object 1 | training selectivity |"));
}

TEST_F(CompareTest, WritesCurvesWithMeanMinMaxAndSdAndPngFigures) {
  ASSERT_EQ(CompareSweepInto(root_ / "out"), 0);
  // srics at 2000 steps: mean 0.12, min 0.10, max 0.14 over 2 seeds, sample sd sqrt(2 * 0.02^2)
  // = 0.0282843; at 1000: 0.05 and 0.2, sd sqrt(2 * 0.075^2) = 0.106066 (blocks: smorl, srics)
  const std::string dat = ReadFile(root_ / "out" / "relational-4-distance.dat");
  EXPECT_THAT(dat, HasSubstr("# srics\n1000 0.125 0.05 0.2 2 0.106066\n2000 0.12 0.1 0.14 2 0.0282843\n")) << dat;
  EXPECT_THAT(dat, HasSubstr("# smorl\n1000 0.25 0.25 0.25 1 0\n")) << dat;
  const std::string selectivity = ReadFile(root_ / "out" / "relational-4-selectivity.dat");
  EXPECT_THAT(selectivity, HasSubstr("2000 0.6 0.5 0.7 2 0.141421")) << selectivity;
  // the band is mean ± 1 sd (the paper's), the legend below the plot, the title whole
  const std::string script = ReadFile(root_ / "out" / "relational-4.gnuplot");
  EXPECT_THAT(script, HasSubstr("using 1:($2-$6):($2+$6) with filledcurves")) << script;
  EXPECT_THAT(script, HasSubstr("set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2")) << script;
  EXPECT_THAT(script,
              HasSubstr("relational-4: average distance of all entities, arm included (mean, band ±1 sd over seeds)"));
  for (const char* name : {"relational-4-distance.png", "relational-4-object_distance.png",
                           "relational-4-subgoal_success.png", "relational-4-selectivity.png", "results.md"}) {
    const fs::path path = root_ / "out" / name;
    ASSERT_TRUE(fs::exists(path)) << name;
    EXPECT_GT(fs::file_size(path), path.extension() == ".png" ? 5000u : 500u) << name;
  }
  EXPECT_EQ(ReadFile(root_ / "out" / "relational-4-distance.png").substr(1, 3), "PNG");
}

// A run that has just started (only the passive policy evaluated) draws nothing, and the
// legends name only the seeds they draw (the campaign's figure said "srics (2 seeds)" over one
// curve while seed 2 was starting).
TEST_F(CompareTest, LegendsCountOnlySeedsWithEvaluations) {
  Write("smorl-seed2", Row(0, 0, 0.31, 0.29, "0;0"), "");
  ASSERT_EQ(CompareSweepInto(root_ / "out"), 0);
  const std::string script = ReadFile(root_ / "out" / "relational-4.gnuplot");
  EXPECT_THAT(script, HasSubstr("title 'smorl (1 seed)'")) << script;
  EXPECT_THAT(script, HasSubstr("title 'srics (2 seeds)'")) << script;
  EXPECT_THAT(script, Not(HasSubstr("smorl (2 seeds)"))) << script;
}

// A learned graph as graph_service writes it: the given edges of 5 entities, action on the arm.
void WriteGraph(const fs::path& run, const std::vector<std::pair<int, int>>& edges) {
  std::vector<double> scores(25, 0.0);
  for (auto [i, j] : edges) scores[i * 5 + j] = 0.5;
  graph_file::LearnedGraph g = graph_file::AggregateGraph(5, scores, 0.06, 0);
  g.version = 1;
  for (int i = 0; i < 5; ++i) g.entity_kinds.push_back(i), g.action_correlation.push_back(i == 0 ? 1.0 : 0.0);
  graph_file::SaveGraph(g, (run / "graph.json").string());
  // relational-4's table as the effective config.yaml holds it: a static puck, a rope 2-3
  std::ofstream(run / "config.yaml") << "env:\n  objects:\n    - {static: true}\n    - {}\n    - {}\n    - {}\n"
                                        "  connections:\n    - {objects: [2, 3], kind: rope, length: 0.13}\n";
}

TEST_F(CompareTest, ListsEachLearnedGraphAgainstTheGraphByConstruction) {
  WriteGraph(sweep_ / "srics-seed1", {{0, 2}, {0, 3}, {0, 4}, {3, 2}});          // the rope one way only
  WriteGraph(sweep_ / "srics-seed2", {{0, 2}, {0, 3}, {0, 4}, {2, 3}, {3, 2}});  // exact
  std::vector<std::string> warnings;
  const std::vector<RunData> runs = ReadRuns({sweep_.string()}, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings[0];
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[0].graph, "");  // smorl learns no graph
  EXPECT_EQ(runs[1].graph, "action->0, 0->2, 0->3, 0->4, 3->2");
  EXPECT_EQ(runs[1].graph_by_construction, "action->0, 0->2, 0->3, 0->4, 2->3, 3->2");
  const std::string table = FinalTable(runs);
  EXPECT_THAT(table, HasSubstr("| srics-seed1 | action->0, 0->2, 0->3, 0->4, 3->2 | "
                               "action->0, 0->2, 0->3, 0->4, 2->3, 3->2 | no |"))
      << table;
  EXPECT_THAT(table, HasSubstr("| srics-seed2 | action->0, 0->2, 0->3, 0->4, 2->3, 3->2 | "
                               "action->0, 0->2, 0->3, 0->4, 2->3, 3->2 | yes |"))
      << table;
  EXPECT_THAT(table, Not(HasSubstr("| smorl-seed1 | action"))) << table;
}

// The campaign's raw folders keep graph.json, not graph.png: compare draws the picture itself
// (graphviz), into an output folder whose name needs shell quoting.
TEST_F(CompareTest, DrawsTheLearnedGraphOfARunWithoutAPicture) {
  WriteGraph(sweep_ / "srics-seed1", {{0, 2}, {0, 3}, {0, 4}, {2, 3}, {3, 2}});
  ASSERT_FALSE(fs::exists(sweep_ / "srics-seed1" / "graph.png"));
  const fs::path out = root_ / "it's out";
  ASSERT_EQ(CompareSweepInto(out), 0);
  const std::string png = ReadFile(out / "relational-4-srics-seed1-graph.png");
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_FALSE(fs::exists(out / "relational-4-smorl-seed1-graph.png"));  // smorl learns no graph
}

TEST_F(CompareTest, ACorruptGraphFileIsNamedAndTheRunStillCounts) {
  fs::create_directories(sweep_ / "srics-seed1");
  std::ofstream(sweep_ / "srics-seed1" / "graph.json") << "{ not a graph";
  std::vector<std::string> warnings;
  const std::vector<RunData> runs = ReadRuns({sweep_.string()}, &warnings);
  EXPECT_EQ(runs.size(), 3u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("srics-seed1/graph.json"));
}

// eval.csv since 2026-12-04 counts, per evaluation, the solved non-ancestor objects the attempts
// began with and how many they undid: compare pools evaluators (3 of 10 at 2000 steps, not the
// mean of 1/4 and 2/6), draws the share, and its second table holds the mean of the last five
// evaluations, the final share and the final evaluation of the last checkpoint (final-eval/).
TEST_F(CompareTest, UndoneShareLastFiveAndTheFinalEvaluationOfTheLastCheckpoint) {
  const std::string header =
      "wall_time,run_id,actor_id,policy_version,graph_version,env_steps,episodes,avg_distance,avg_object_distance,"
      "success_rate,selectivity,entity_distance,subgoal_success,independent_solved,independent_undone\n";
  const fs::path run = sweep_ / "srics-seed2";
  std::ofstream(run / "eval.csv") << header << "1.0,r,0,0,1,0,5,0.32,0.30,0.5,0.4,0.1;0.1,0;0,0,0\n"
                                  << "1.0,r,0,3,1,1000,5,0.20,0.18,0.5,0.4,0.1;0.1,1;0,10,5\n"
                                  << "1.0,r,0,6,1,2000,5,0.13,0.10,0.5,0.4,0.1;0.1,0.5;0.6,4,1\n"
                                  << "1.0,r,1,6,1,2000,5,0.15,0.12,0.5,0.4,0.1;0.1,1;0.6,6,2\n";
  fs::create_directories(run / "final-eval");
  std::ofstream(run / "final-eval" / "episodes.csv")
      << "episode,seed,status,steps,frames,avg_distance,avg_object_distance\n"
      << "0,1,ok,180,0,0.1,0.12\n1,2,ok,180,0,0.2,0.18\n2,3,unstable,5,0,9,9\n";
  std::ofstream(run / "final-eval" / "attempts.csv")
      << "episode,attempt,entity,skipped,distance_before,distance_after,reached,others_solved,others_undone,"
         "independent_solved,independent_undone\n"
      << "0,0,2,0,0.1,0.1,0,3,1,3,1\n0,1,3,0,0.1,0.1,0,1,0,1,0\n"
      // the arm's attempt and one at the static puck 1: in the undone share, not in the object attempts'
      << "1,0,0,0,0.1,0.1,1,5,4,5,4\n1,1,1,0,0.1,0.1,0,2,0,2,0\n";
  // the run's config: Relational Rearrange 4 (arm 0, static puck 1, pucks 2-4 movable)
  std::ofstream(run / "config.yaml") << "extends: " << SRICS_SOURCE_DIR << "/deploy/configs/relational-4.yaml\n";
  fs::create_directories(run / "final-eval-passive");
  std::ofstream(run / "final-eval-passive" / "episodes.csv")
      << "episode,seed,status,steps,frames,avg_distance,avg_object_distance\n0,1,ok,180,0,0.3,0.3\n1,2,ok,180,0,0.3,0."
         "3\n";

  std::vector<std::string> warnings;
  const std::string table = FinalTable(ReadRuns({sweep_.string()}, &warnings));
  EXPECT_TRUE(warnings.empty()) << warnings[0];
  // srics: only the finished seed 2 counts; last five = its two evaluations (0.20 and the two
  // evaluators' 0.14); final share 3 / 10; final-eval: the two good episodes, of all attempts
  // 11 solved 5 undone (0.45), of the attempts on movable objects 2 and 3: 4 solved 1 undone
  EXPECT_THAT(table, HasSubstr("| srics | 1 | 0.170 ± 0.000 | 0.145 ± 0.000 | 0.30 ± 0.00 | 2 x 1 | 0.150 ± 0.000 | "
                               "0.150 ± 0.000 | 0.50 ± 0.00 | 0.45 ± 0.00 | 0.25 ± 0.00 |"))
      << table;
  // smorl's eval.csv predates the columns and it has no final-eval/
  EXPECT_THAT(table, HasSubstr("| smorl | 1 | 0.225 ± 0.000 | 0.190 ± 0.000 | - | - | - | - | - | - | - |")) << table;

  // a run whose episodes draw object sets: attempts.csv's entities are places in the episode, so
  // the object attempts' share is not made
  std::ofstream(run / "config.yaml") << "extends: " << SRICS_SOURCE_DIR
                                     << "/deploy/configs/campaign/rearrange-4-unseen.yaml\n";
  const std::string with_sets = FinalTable(ReadRuns({sweep_.string()}, &warnings));
  EXPECT_THAT(with_sets, HasSubstr("| 0.50 ± 0.00 | 0.45 ± 0.00 | - |")) << with_sets;

  ASSERT_EQ(CompareSweepInto(root_ / "out"), 0);
  const std::string dat = ReadFile(root_ / "out" / "relational-4-undone.dat");
  EXPECT_THAT(dat, HasSubstr("# srics\n1000 0.5 0.5 0.5 1 0\n2000 0.3 0.3 0.3 1 0\n")) << dat;
  EXPECT_GT(fs::file_size(root_ / "out" / "relational-4-undone.png"), 5000u);
}

// Issue 38: the methods' panel apart from the ablations', in one folder; the band as min-max on request.
TEST_F(CompareTest, MethodsPickAPanelAndBandMinMaxIsAnOption) {
  CompareOptions options;
  options.dirs = {sweep_.string()};
  options.out_dir = (root_ / "out").string();
  options.methods = {"srics"};
  options.panel = "methods";
  options.band = CompareOptions::Band::kMinMax;
  ASSERT_EQ(Compare(options), 0);
  const std::string dat = ReadFile(root_ / "out" / "relational-4-methods-distance.dat");
  EXPECT_THAT(dat, HasSubstr("# srics\n"));
  EXPECT_THAT(dat, Not(HasSubstr("# smorl")));
  const std::string script = ReadFile(root_ / "out" / "relational-4-methods.gnuplot");
  EXPECT_THAT(script, HasSubstr("using 1:3:4 with filledcurves"));
  EXPECT_THAT(script, HasSubstr("relational-4 (methods): average object distance (mean, band min-max over seeds)"));
  EXPECT_TRUE(fs::exists(root_ / "out" / "relational-4-methods-distance.png"));
  EXPECT_THAT(ReadFile(root_ / "out" / "results-methods.md"), Not(HasSubstr("| smorl |")));
  // a method no run has is named, the others still drawn
  options.methods = {"srics", "hac"};
  testing::internal::CaptureStderr();
  EXPECT_EQ(Compare(options), 0);
  EXPECT_THAT(testing::internal::GetCapturedStderr(), HasSubstr("--methods: no run of method 'hac'"));
}

TEST_F(CompareTest, NoRunsIsAnError) {
  CompareOptions options;
  options.dirs = {(root_ / "nothing").string()};
  options.out_dir = (root_ / "out").string();
  EXPECT_EQ(Compare(options), 1);
}

}  // namespace
}  // namespace srics::analysis
