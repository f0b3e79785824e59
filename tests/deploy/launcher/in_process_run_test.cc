// `srics run --in-process`: the distributed run's loops wired in memory. The same config
// gives the same eval.csv bit for bit (wall-clock column aside), the run folder holds what the
// distributed run leaves, and the last evaluation is of the final weights.

#include "deploy/launcher/in_process_run.h"

#include "common/config/config.h"
#include "deploy/run_folder/outcome.h"
#include "graph_service/service.h"
#include "tests/deploy/tiny_run.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;

std::string Config(const std::string& name) { return std::string(SRICS_SOURCE_DIR) + "/deploy/configs/" + name; }

const std::vector<std::string> kSmallRun =
    srics::testing::TinyRunSettings({"run.total_env_steps=1200", "learner.checkpoint_every_updates=300",
                                     "actors.count=2", "actors.eval_every_env_steps=400"});

// eval.csv without its first column (wall_time)
std::string EvalRows(const std::string& dir) {
  std::ifstream in(dir + "/eval.csv");
  std::stringstream out;
  std::string line;
  while (std::getline(in, line)) out << line.substr(line.find(',') + 1) << "\n";
  return out.str();
}

int RunOnce(const std::string& dir, const std::vector<std::string>& more = {},
            const std::string& config = "rearrange-1-cpu.yaml") {
  fs::remove_all(dir);
  LaunchOptions options;
  options.config_file = Config(config);
  options.overrides = kSmallRun;
  options.overrides.insert(options.overrides.end(), more.begin(), more.end());
  options.run_dir = dir;
  options.display = DisplayMode::kNone;
  options.in_process = true;
  return Run(options);
}

TEST(InProcessRunTest, SameConfigSameEvalCsvAndAWholeRunFolder) {
  const std::string a = ::testing::TempDir() + "/in_process_a", b = ::testing::TempDir() + "/in_process_b";
  ASSERT_EQ(RunOnce(a), kExitDone);
  ASSERT_EQ(RunOnce(b), kExitDone);
  const std::string rows = EvalRows(a);
  // the passive baseline, evaluations at 400 and 800 env steps and the final one
  EXPECT_GE(std::count(rows.begin(), rows.end(), '\n'), 4) << rows;
  EXPECT_EQ(rows, EvalRows(b));
  for (const char* file : {"config.yaml", "resolved-config.yaml", "eval.csv", "learner.csv", "nodes.csv", "graph.json",
                           "checkpoint.srics", "summary.txt", "logs/launcher.log"})
    EXPECT_TRUE(fs::exists(fs::path(a) / file)) << file;
  // what the launch cost: a whole small run takes a second of CPU or more, less than the test's
  const auto outcome = run_folder::ReadRunOutcome(a);
  ASSERT_TRUE(outcome.has_value());
  EXPECT_EQ(outcome->state, "finished");
  EXPECT_GT(outcome->cpu_seconds, 1.0);
  EXPECT_LT(outcome->cpu_seconds, 120.0);
}

// run.in_process_threads: 2, the learner on its own thread: as deterministic as one thread (the
// bus holds each round's publications and delivers them in a fixed order), a whole run folder,
// and a run of its own (the learner sees each round's episodes a round later).
TEST(InProcessRunTest, TwoThreadsSameEvalCsvEveryTime) {
  const std::string a = ::testing::TempDir() + "/in_process_2t_a", b = ::testing::TempDir() + "/in_process_2t_b";
  ASSERT_EQ(RunOnce(a, {"run.in_process_threads=2"}), kExitDone);
  ASSERT_EQ(RunOnce(b, {"run.in_process_threads=2"}), kExitDone);
  const std::string rows = EvalRows(a);
  EXPECT_GE(std::count(rows.begin(), rows.end(), '\n'), 4) << rows;
  EXPECT_EQ(rows, EvalRows(b));
  for (const char* file : {"eval.csv", "learner.csv", "nodes.csv", "checkpoint.srics", "summary.txt"})
    EXPECT_TRUE(fs::exists(fs::path(a) / file)) << file;
  const std::string one = ::testing::TempDir() + "/in_process_1t";
  ASSERT_EQ(RunOnce(one), kExitDone);
  EXPECT_NE(rows, EvalRows(one));
}

// graph.object_ties: joint on Relational Rearrange 4 with the campaign's two-way graph: a whole
// run trains and evaluates the tied pucks as one subgoal of two goal tokens; the learner takes
// every training episode (the pair's 4-float goals too), and the run's evaluations are there.
TEST(InProcessRunTest, JointTiesRunEndToEnd) {
  const std::string dir = ::testing::TempDir() + "/in_process_joint";
  ASSERT_EQ(
      RunOnce(dir, {"graph.object_ties=joint", "graph.file=" + Config("campaign/graphs/relational-4-two-way.json")},
              "relational-4.yaml"),
      kExitDone);
  std::ifstream learner(dir + "/learner.csv");
  std::string header, line, last;
  std::getline(learner, header);
  while (std::getline(learner, line)) last = line;
  std::stringstream h(header), r(last);
  std::map<std::string, std::string> row;
  for (std::string key, value; std::getline(h, key, ',') && std::getline(r, value, ',');) row[key] = value;
  ASSERT_TRUE(row.count("episodes_rejected")) << header;
  EXPECT_EQ(row["episodes_rejected"], "0");
  EXPECT_NE(row["episodes_accepted"], "0");
  const std::string rows = EvalRows(dir);
  EXPECT_GE(std::count(rows.begin(), rows.end(), '\n'), 3) << rows;
}

// Every actor gets its share of the env steps the learner allows. Actors used to count the rate
// limit from where each had started: the one that started at the larger lag took every
// allowance (here 3,640 env steps against 620; in the campaign 182,100 against 32,800).
TEST(InProcessRunTest, ActorsShareTheEnvSteps) {
  const std::string dir = ::testing::TempDir() + "/in_process_share";
  // a small error buffer: the learner holds the actors back for most of the run, as in long runs
  ASSERT_EQ(RunOnce(dir, {"learner.rate_error_buffer=10", "run.total_env_steps=3000"}), kExitDone);
  std::ifstream in(dir + "/nodes.csv");
  std::string line;
  std::getline(in, line);  // wall_time,run_id,role,node_id,host,pid,state,policy_version,graph_version,env_steps,...
  std::map<std::string, uint64_t> steps;  // each actor's last report
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (cells.size() > 9 && cells[2] == "actor") steps[cells[3]] = std::stoull(cells[9]);
  }
  ASSERT_EQ(steps.size(), 2u);
  const double total = static_cast<double>(steps["0"] + steps["1"]);
  EXPECT_GE(total, 3000);
  for (const auto& [actor, n] : steps) EXPECT_GE(n / total, 0.3) << "actor " << actor << ": " << n << " of " << total;
}

// The final evaluation is of the learner's final weights (their version is in eval.csv's
// last row and in the learner's last stats), with one thread and with two.
class FinalWeightsTest : public ::testing::TestWithParam<int> {};

TEST_P(FinalWeightsTest, TheLastEvaluationUsesTheFinalWeights) {
  const std::string dir = ::testing::TempDir() + "/in_process_final_" + std::to_string(GetParam());
  ASSERT_EQ(RunOnce(dir, {"run.in_process_threads=" + std::to_string(GetParam())}), kExitDone);
  auto last_row = [](const std::string& path) {
    std::ifstream in(path);
    std::string header, line, last;
    std::getline(in, header);
    while (std::getline(in, line)) last = line;
    return std::make_pair(header, last);
  };
  auto column = [](const std::pair<std::string, std::string>& csv, const std::string& name) {
    std::stringstream h(csv.first), r(csv.second);
    std::string key, value;
    while (std::getline(h, key, ',') && std::getline(r, value, ','))
      if (key == name) return value;
    return std::string("missing");
  };
  const auto eval = last_row(dir + "/eval.csv");
  const auto stats = last_row(dir + "/learner.csv");
  EXPECT_EQ(column(eval, "policy_version"), column(stats, "policy_version"));
  EXPECT_EQ(column(eval, "env_steps"), "1200");
}

INSTANTIATE_TEST_SUITE_P(InProcessRunTest, FinalWeightsTest, ::testing::Values(1, 2),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return std::to_string(info.param) + "_threads";
                         });

// actors.record_eval_episodes: every evaluation of a trained policy leaves its first episode
// drawn in eval/ (GIF or PNG frames), listed in eval/recorded.csv with the metrics the
// evaluation reported for it (a drawn episode is the same episode), one frame per state.
TEST(InProcessRunTest, EvaluationsRecordTheirFirstEpisodeIntoTheRunFolder) {
  const std::string dir = ::testing::TempDir() + "/in_process_record";
  fs::remove_all(dir);
  LaunchOptions options;
  options.config_file = Config("rearrange-1-cpu.yaml");
  options.overrides = kSmallRun;
  for (const char* o :
       {"actors.eval_episodes=1", "actors.record_eval_episodes=1", "actors.record_width=64", "actors.record_height=48"})
    options.overrides.push_back(o);
  options.run_dir = dir;
  options.display = DisplayMode::kNone;
  options.in_process = true;
  ASSERT_EQ(launcher::Run(options), kExitDone);

  // eval.csv: policy_version (col 3) -> avg_distance (col 7) of the evaluation's one episode
  std::map<std::string, double> evaluated;
  {
    std::ifstream in(dir + "/eval.csv");
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      std::vector<std::string> f;
      std::stringstream row(line);
      for (std::string v; std::getline(row, v, ',');) f.push_back(v);
      if (f.size() > 7 && f[3] != "0") evaluated[f[3]] = std::stod(f[7]);
    }
  }
  ASSERT_GE(evaluated.size(), 2u);
  std::ifstream in(dir + "/eval/recorded.csv");
  std::string header, line;
  ASSERT_TRUE(std::getline(in, header)) << "no eval/recorded.csv";
  EXPECT_EQ(
      header,
      "policy_version,actor_id,seed,status,steps,frames,avg_distance,avg_object_distance,success,selectivity,video");
  size_t rows = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream row(line);
    for (std::string v; std::getline(row, v, ',');) f.push_back(v);
    ASSERT_EQ(f.size(), 11u) << line;
    ++rows;
    EXPECT_EQ(f[3], "ok");
    EXPECT_EQ(std::stoi(f[5]), std::stoi(f[4]) + 1) << "one frame per state, the reset's included";
    ASSERT_TRUE(evaluated.count(f[0])) << "recorded a version that was not evaluated: " << f[0];
    EXPECT_NEAR(std::stod(f[6]), evaluated[f[0]], 1e-5) << "the drawn episode is the evaluated one";
    const fs::path media = fs::path(dir) / "eval" / f[10];
    ASSERT_TRUE(fs::exists(media)) << media;
    if (fs::is_directory(media))
      EXPECT_TRUE(fs::exists(media / "frame-00000.png"));
    else
      EXPECT_GT(fs::file_size(media), 100u);
  }
  EXPECT_EQ(rows, evaluated.size()) << "one recorded episode per evaluation of a trained policy";
}

}  // namespace
}  // namespace srics::launcher

namespace srics::launcher {
namespace {

// graph.refine_after_publish in a real run: the graph service takes the MuJoCo actors' own
// training episodes (none refused), trains on them, and the run ends as usual.
TEST(InProcessRunTest, RefinementTakesInTheActorsTrainingEpisodes) {
  std::vector<std::string> overrides = kSmallRun;
  overrides.push_back("graph.refine_after_publish=true");
  const config::Config config = config::LoadConfig(Config("rearrange-1-cpu.yaml"), overrides);
  const std::string dir = ::testing::TempDir() + "/in_process_refine";
  fs::remove_all(dir);
  fs::create_directories(dir);
  InProcessRun run(config, dir, nullptr);
  while (run.Round()) {
  }
  const graph_service::Progress& p = run.graph_service()->progress();
  EXPECT_TRUE(p.refining);
  // 1200 env steps of 20-step training episodes, less the explore and evaluation steps
  EXPECT_GT(p.refine_episodes, 20);
  EXPECT_EQ(p.dropped, 0) << p.last_drop_reason;
  EXPECT_GT(p.updates, 40 + 5 * 20) << "refine_updates_per_episode (5) per episode taken in";
  EXPECT_TRUE(fs::exists(dir + "/graph_training.srics")) << "kept for the refinement to resume";
}

}  // namespace
}  // namespace srics::launcher
