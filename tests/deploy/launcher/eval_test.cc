// `srics eval` on the checkpoint of a tiny in-process run made here: the metrics file has a row
// per episode with the protocol's figures, and each video holds one frame per env step plus
// the first state, decoded again and looked at (not blank, changing, the hand moving). Bad
// arguments exit 2 naming the argument; a missing or corrupt checkpoint exits 1 saying so.

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "actor/env/render/video_writer.h"
#include "common/rl/seeds.h"
#include "deploy/launcher/child_process.h"
#include "deploy/launcher/launcher.h"
#include "deploy/launcher/run_folder.h"
#include "deploy/run_folder/csv.h"
#include "deploy/run_folder/outcome.h"
#include "tests/actor/env/render/frames_testing.h"
#include "tests/common/files/test_files.h"
#include "tests/deploy/launcher/sweep_testing.h"

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;
using env::testing::DecodeVideo;
using env::testing::DifferingPixels;
using env::testing::FindHand;
using env::testing::PixelStdDev;
using env::testing::ReadPng;
using files::testing::ReadFile;
using ::testing::HasSubstr;

// `srics eval ARGS...`: the exit code and the output.
std::pair<int, std::string> SricsEval(const fs::path& root, std::vector<std::string> args) {
  args.insert(args.begin(), {SRICS_LAUNCHER, "eval"});
  const std::string out = (root / "eval.out").string();
  fs::remove(out);
  ChildProcess child = ChildProcess::Spawn(args, {.output_file = out});
  const auto status = child.WaitFor(std::chrono::seconds(240));
  if (!status) return {-1, "timeout"};
  return {status->signaled ? -status->code : status->code, files::testing::ReadFile(out)};
}

// episodes.csv as rows of column -> value.
std::vector<std::map<std::string, std::string>> ReadCsv(const fs::path& path) {
  std::vector<std::map<std::string, std::string>> rows;
  const std::optional<run_folder::CsvTable> table = run_folder::CsvTable::Read(path);
  if (!table) return rows;
  for (const run_folder::CsvRow& fields : table->Rows()) {
    if (fields.fields().size() != table->header().size())
      ADD_FAILURE() << path << ": a row of " << fields.fields().size() << " fields under " << table->header().size()
                    << " columns";
    std::map<std::string, std::string> row;
    for (const std::string& column : table->header()) row[column] = fields.Text(column);
    rows.push_back(row);
  }
  return rows;
}

// The tiny SRICS run (learned graph, checkpoint) every test evaluates. ctest runs each test in
// its own process, maybe two at once: the first makes the run under a lock, the others reuse
// it while it is newer than the srics program.
int MakeOrReuseTinyRun(const fs::path& dir) {
  fs::create_directories(dir.parent_path());
  const int lock = open((dir.string() + ".lock").c_str(), O_CREAT | O_RDWR, 0644);
  if (lock < 0 || flock(lock, LOCK_EX) != 0) return -1;
  const auto outcome = run_folder::ReadRunOutcome(dir.string());
  std::error_code error;
  const bool fresh = outcome && outcome->state == "finished" &&
                     fs::last_write_time(dir / "outcome.yaml", error) > fs::last_write_time(SRICS_LAUNCHER, error);
  int code = kExitDone;
  if (!fresh) {
    fs::remove_all(dir);
    LaunchOptions options;
    options.config_file = testing::kConfig;
    options.overrides = testing::kTinyRun;
    options.run_dir = dir.string();
    options.display = DisplayMode::kNone;
    options.in_process = true;
    code = Run(options);
  }
  close(lock);  // releases the lock
  return code;
}

// The trained policy committed with the results (docs/results.md: Relational Rearrange 4, SRICS
// seed 1) and a scratch folder per test, removed after it.
class CommittedPolicyTest : public ::testing::Test {
 protected:
  static fs::path Policy() {
    return fs::path(SRICS_SOURCE_DIR) / "docs/results/campaign/policy-relational-4-srics-seed1";
  }
  // A fresh, empty folder of this test.
  fs::path Scratch(const std::string& name) { return scratch_.emplace("srics_" + name).path(); }
  // `dir` made a run folder of the committed policy: its config and graph, and its checkpoint
  // when asked.
  static fs::path AsRunFolder(const fs::path& dir, bool with_checkpoint) {
    fs::create_directories(dir);
    fs::copy_file(Policy() / "config.yaml", dir / "config.yaml");
    fs::copy_file(Policy() / "graph.json", dir / "graph.json");
    if (with_checkpoint) fs::copy_file(Policy() / "policy.srics", dir / "checkpoint.srics");
    return dir;
  }
  // srics eval's arguments that load the committed policy with its config and graph.
  static std::vector<std::string> PolicyArgs(std::vector<std::string> extra) {
    std::vector<std::string> args = {(Policy() / "policy.srics").string(), "--config",
                                     (Policy() / "config.yaml").string(), "--graph",
                                     (Policy() / "graph.json").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }

 private:
  std::optional<files::testing::ScratchFolder> scratch_;
};

// The mean of a column over the rows.
double MeanOf(const std::vector<std::map<std::string, std::string>>& rows, const std::string& column) {
  double sum = 0;
  for (const auto& row : rows) sum += std::stod(row.at(column));
  return rows.empty() ? 0 : sum / rows.size();
}

// The committed policy still loads and still moves the pucks: over the protocol's 20 episodes its object
// distance stays well under the passive policy's 0.1875 (0.122 when it was committed). Fails
// when a change of the checkpoint format or of the networks leaves the file behind.
TEST_F(CommittedPolicyTest, RelationalFourPolicyPlaysBetterThanPassive) {
  const fs::path out = Scratch("committed_policy");
  const auto [code, output] = SricsEval(out, PolicyArgs({"--episodes", "20", "--no-video", "--out", out.string()}));
  ASSERT_EQ(code, 0) << output;
  const auto rows = ReadCsv(out / "episodes.csv");
  ASSERT_EQ(rows.size(), 20u) << output;
  EXPECT_LT(MeanOf(rows, "avg_object_distance"), 0.16) << output;

  // attempts.csv: the reference schedule of every episode (9 attempts, the paper's 2(n + 1) - 1 for
  // its 4 objects: 5 cycling through the 4 subgoals, the arm and pucks 2-4 (the static puck 1 has
  // none), then the 4 in depth order), fewer only when every subgoal was solved early; each
  // attempt that was not skipped took 20 steps, a skipped one started solved, and the last
  // attempt ends where the episode does.
  const auto attempts = ReadCsv(out / "attempts.csv");
  std::vector<std::vector<std::map<std::string, std::string>>> by_episode(rows.size());
  for (const auto& a : attempts) by_episode.at(std::stoul(a.at("episode"))).push_back(a);
  int full_length = 0, total_solved = 0;
  // (attempted entity, other object) -> (solved at the attempt's start, undone by it)
  std::map<std::pair<int, int>, std::pair<int, int>> by_pair;
  // attempted entity -> (solved objects undone before it moved, undone)
  std::map<int, std::pair<int, int>> undone_early;
  for (size_t episode = 0; episode < rows.size(); ++episode) {
    const auto& list = by_episode[episode];
    ASSERT_FALSE(list.empty()) << "episode " << episode;
    ASSERT_LE(list.size(), 9u) << "episode " << episode;
    if (list.size() < 5) {
      // over in the cycling phase: every subgoal but the one just attempted is solved
      for (const char* entity : {"0", "2", "3", "4"})
        if (list.back().at("entity") != entity)
          EXPECT_LT(std::stod(rows[episode].at(std::string("distance_") + entity)), 0.05)
              << "episode " << episode << " ended early with subgoal " << entity << " unsolved";
    }
    full_length += list.size() == 9;
    int played = 0;
    for (size_t k = 0; k < list.size(); ++k) {
      const auto& a = list[k];
      ASSERT_EQ(std::stoul(a.at("attempt")), k);
      const int entity = std::stoi(a.at("entity"));
      EXPECT_NE(entity, 1) << "the static puck has no subgoal";
      const double before = std::stod(a.at("distance_before")), after = std::stod(a.at("distance_after"));
      if (a.at("skipped") == "1") {
        EXPECT_GE(k, 5u) << "in the first 5 a solved subgoal hands its slot on";
        EXPECT_LT(before, 0.05);
        EXPECT_EQ(before, after);
      } else {
        // the first is drawn unchecked; the cycling phase passes over solved ones
        if (k >= 1 && k < 5) EXPECT_GE(before, 0.05) << "episode " << episode << " attempt " << k;
        ++played;
      }
      EXPECT_EQ(a.at("reached") == "1", after < 0.05);
      EXPECT_LE(std::stoi(a.at("others_undone")), std::stoi(a.at("others_solved")));
      EXPECT_LE(std::stoi(a.at("independent_undone")), std::stoi(a.at("independent_solved")));
      EXPECT_LE(std::stoi(a.at("independent_solved")), std::stoi(a.at("others_solved")));
      // of the undone ones, those knocked off before the attempted entity moved: a part, none
      // when nothing was undone or the slot took no steps
      const int before_moved = std::stoi(a.at("others_undone_before_moved"));
      EXPECT_GE(before_moved, 0);
      EXPECT_LE(before_moved, std::stoi(a.at("others_undone")));
      if (a.at("skipped") == "1") EXPECT_EQ(before_moved, 0);
      if (a.at("skipped") == "0") {
        undone_early[entity].first += before_moved;
        undone_early[entity].second += std::stoi(a.at("others_undone"));
      }
      // the free puck 4 has only the arm as ancestor: every solved object is independent of it
      if (entity == 4) {
        EXPECT_EQ(a.at("independent_solved"), a.at("others_solved"));
      }
      // every entity's distances at the attempt's start and end: the attempted one's are the
      // scalar columns, and the other objects within 0.05 at the start and outside it at the end
      // are the attempt's undone ones (the arm, entity 0, never counts)
      const std::vector<double> all_before = run_folder::SplitValues(a.at("distances_before"));
      const std::vector<double> all_after = run_folder::SplitValues(a.at("distances_after"));
      ASSERT_EQ(all_before.size(), 5u) << "episode " << episode << " attempt " << k;
      ASSERT_EQ(all_after.size(), 5u) << "episode " << episode << " attempt " << k;
      EXPECT_NEAR(all_before[entity], before, 1e-5);
      EXPECT_NEAR(all_after[entity], after, 1e-5);
      int others_solved = 0, others_undone = 0;
      for (int other : {2, 3, 4}) {
        if (other == entity || all_before[other] >= 0.05) continue;
        ++others_solved;
        others_undone += all_after[other] >= 0.05;
        if (a.at("skipped") == "0") {
          ++by_pair[{entity, other}].first;
          by_pair[{entity, other}].second += all_after[other] >= 0.05;
        }
      }
      EXPECT_EQ(std::stoi(a.at("others_solved")), others_solved) << "episode " << episode << " attempt " << k;
      EXPECT_EQ(std::stoi(a.at("others_undone")), others_undone) << "episode " << episode << " attempt " << k;
      // an attempt starts where the last one ended
      if (k > 0) EXPECT_EQ(a.at("distances_before"), list[k - 1].at("distances_after"));
    }
    EXPECT_EQ(std::stoi(rows[episode].at("steps")), 20 * played) << "episode " << episode;
    // the episode's compatibility counts (what an in-run evaluation sends in EvalResult) are its
    // attempts' sums, the skipped slots (no steps, nothing undone) left out
    int solved = 0, undone = 0;
    for (const auto& a : list)
      if (a.at("skipped") == "0")
        solved += std::stoi(a.at("independent_solved")), undone += std::stoi(a.at("independent_undone"));
    EXPECT_EQ(std::stoi(rows[episode].at("independent_solved")), solved) << "episode " << episode;
    EXPECT_EQ(std::stoi(rows[episode].at("independent_undone")), undone) << "episode " << episode;
    total_solved += solved;
    const auto& last = list.back();
    EXPECT_NEAR(std::stod(last.at("distance_after")), std::stod(rows[episode].at("distance_" + last.at("entity"))),
                1e-4)
        << "episode " << episode;
  }
  EXPECT_GT(full_length, 10) << "the policy seldom solves the whole table";
  EXPECT_GT(total_solved, 20) << "attempts begin with solved objects";
  EXPECT_NE(output.find("attempts on object 4:"), std::string::npos) << output;
  // the summary names which solved object each subgoal's attempts undid: the pairs recounted
  for (const auto& [pair, counts] : by_pair) {
    const std::string line = "solved objects undone by attempts on " +
                             (pair.first == 0 ? std::string("arm") : "object " + std::to_string(pair.first)) + ":";
    const size_t at = output.find(line);
    ASSERT_NE(at, std::string::npos) << line << "\n" << output;
    char share[64];
    std::snprintf(share, sizeof(share), " object %d %.2f of %d,", pair.second,
                  static_cast<double>(counts.second) / counts.first, counts.first);
    EXPECT_NE(output.substr(at, output.find('\n', at) - at).find(share), std::string::npos)
        << "expected '" << share << "' in: " << output.substr(at, output.find('\n', at) - at);
  }
  EXPECT_GE(by_pair.size(), 6u) << "attempts met solved objects of several kinds";
  // the summary's "undone before it had moved" shares are the column's sums; some undoing
  // happens on the hand's way to a puck (measured: about half of it on this policy)
  int early = 0;
  for (const auto& [entity, counts] : undone_early) {
    const std::string line = "solved objects undone by attempts on " +
                             (entity == 0 ? std::string("arm") : "object " + std::to_string(entity)) + ":";
    const size_t at = output.find(line);
    if (counts.second == 0 || at == std::string::npos) continue;
    char share[96];
    std::snprintf(share, sizeof(share), "had moved 1 cm: %.2f of %d", static_cast<double>(counts.first) / counts.second,
                  counts.second);
    EXPECT_NE(output.substr(at, output.find('\n', at) - at).find(share), std::string::npos)
        << "expected '" << share << "' in: " << output.substr(at, output.find('\n', at) - at);
    early += counts.first;
  }
  EXPECT_GT(early, 0) << "no solved object was knocked off before the attempted one moved";
}

// actors.eval_schedule: independent_draws, the campaign's runs to 2026-12-04: 8 attempts on
// Relational Rearrange 4 (4 independent draws, then the 4 subgoals in depth order; a solved
// draw loses its slot), so those runs' evaluations can be replayed as they were.
TEST_F(CommittedPolicyTest, IndependentDrawsScheduleGivesEightAttempts) {
  const fs::path out = Scratch("independent_draws");
  const auto [code, output] = SricsEval(out, PolicyArgs({"--episodes", "10", "--no-video", "--out", out.string(),
                                                         "--set", "actors.eval_schedule=independent_draws"}));
  ASSERT_EQ(code, 0) << output;
  const auto rows = ReadCsv(out / "episodes.csv");
  const auto attempts = ReadCsv(out / "attempts.csv");
  ASSERT_EQ(rows.size(), 10u) << output;
  ASSERT_EQ(attempts.size(), 10u * 8u) << output;
  int skipped_early = 0;
  for (size_t i = 0; i < attempts.size(); ++i) {
    EXPECT_EQ(std::stoul(attempts[i].at("attempt")), i % 8);
    skipped_early += i % 8 < 4 && attempts[i].at("skipped") == "1";
  }
  for (size_t episode = 0; episode < rows.size(); ++episode)
    EXPECT_EQ(attempts[episode * 8 + 7].at("entity"), "0") << "the arm comes last in depth order";
  EXPECT_GT(skipped_early, 0) << "a solved draw of the first phase loses its slot";
}

// --passive plays the passive baseline on the run's goals from a folder with no checkpoint in
// it: over the protocol's 20 episodes its object distance is the passive row of the run's
// eval.csv (0.1875052 at 0 env steps, docs/results/campaign/raw/relational-4-srics/srics-seed1),
// and the policy's own evaluation of the same folder still needs the checkpoint.
TEST_F(CommittedPolicyTest, PassiveBaselineNeedsNoCheckpointAndIsTheRunsPassiveRow) {
  const fs::path out = Scratch("passive");
  AsRunFolder(out / "run", /*with_checkpoint=*/false);
  const auto [code, output] = SricsEval(
      out, {(out / "run").string(), "--passive", "--episodes", "20", "--no-video", "--out", (out / "eval").string()});
  ASSERT_EQ(code, 0) << output;
  EXPECT_THAT(output, HasSubstr("the passive baseline"));
  const auto rows = ReadCsv(out / "eval/episodes.csv");
  ASSERT_EQ(rows.size(), 20u) << output;
  EXPECT_NEAR(MeanOf(rows, "avg_object_distance"), 0.1875052, 1e-4) << output;

  const auto [policy_code, policy_output] =
      SricsEval(out, {(out / "run").string(), "--episodes", "1", "--no-video", "--out", (out / "eval2").string()});
  EXPECT_EQ(policy_code, 1) << policy_output;
  EXPECT_THAT(policy_output, HasSubstr("no checkpoint"));
}

// The same policy on fewer objects than it trained with (env.eval_object_sets: pucks 1-3, the
// free puck 4 left out), as `srics eval --seen --unseen` plays combinations: episodes.csv has the
// distances of the arm and the three pucks, and the free puck never gets an attempt. `srics
// eval` refused it before ("episode 0 has another number of entities": it counted the entities
// of the training objects).
TEST_F(CommittedPolicyTest, PlaysFewerObjectsThanItTrainedWith) {
  const fs::path out = Scratch("fewer_objects");
  const auto [code, output] = SricsEval(out, PolicyArgs({"--set", "env.eval_object_sets=[{present: [1, 2, 3]}]",
                                                         "--episodes", "3", "--no-video", "--out", out.string()}));
  ASSERT_EQ(code, 0) << output;
  const auto rows = ReadCsv(out / "episodes.csv");
  ASSERT_EQ(rows.size(), 3u) << output;
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("status"), "ok");
    EXPECT_TRUE(row.count("distance_3")) << "pucks 1-3 and the arm";
    EXPECT_FALSE(row.count("distance_4")) << "puck 4 is not there";
  }
  for (const auto& attempt : ReadCsv(out / "attempts.csv")) EXPECT_LE(std::stoi(attempt.at("entity")), 3);
}

// `srics eval --seen --unseen` on the committed policy (as a run folder: its checkpoint, config and
// graph), all four pucks as the "seen" combination and pucks 1-3 as the "unseen" one: a row per
// combination whose ratio is the policy's object distance over the passive baseline's, the
// passive figure that of `srics eval --passive` on the same objects, and the per-run table.
TEST_F(CommittedPolicyTest, SeenUnseenStudyDividesEachCombinationByItsPassiveBaseline) {
  const fs::path root = Scratch("seen_unseen");
  AsRunFolder(root / "run-a", /*with_checkpoint=*/true);
  const fs::path out = root / "out";
  // refused before anything is played: a combination that is not ids, two held-out ones, both studies
  for (const std::vector<std::string>& bad : {std::vector<std::string>{"--seen", "1,x", "--unseen", "1,2,3"},
                                              {"--seen", "1,2,3,4", "--unseen", "1,2 1,3"},
                                              {"--seen", "1,2,3,4", "--unseen", "1,2,3", "--cross-protocol"}}) {
    std::vector<std::string> args = bad;
    args.insert(args.end(), {"--out", (root / "refused").string(), (root / "run-a").string()});
    const auto [bad_code, bad_output] = SricsEval(root, args);
    EXPECT_EQ(bad_code, 2) << bad_output;
    EXPECT_FALSE(fs::exists(root / "refused" / "raw" / "run-a-objects1-2-3-4-policy")) << bad_output;
  }
  const auto [study_code, output] = SricsEval(root, {"--seen", "1,2,3,4", "--unseen", "1,2,3", "--episodes", "2",
                                                     "--out", out.string(), (root / "run-a").string()});
  ASSERT_EQ(study_code, 0) << output;
  const auto rows = ReadCsv(out / "seen-unseen.csv");
  ASSERT_EQ(rows.size(), 2u) << output;
  EXPECT_EQ(rows[0].at("combination"), "1 2 3 4");
  EXPECT_EQ(rows[0].at("kind"), "seen");
  EXPECT_EQ(rows[1].at("combination"), "1 2 3");
  EXPECT_EQ(rows[1].at("kind"), "unseen");
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("episodes"), "2");
    const double policy_distance = std::stod(row.at("object_distance")),
                 passive = std::stod(row.at("passive_object_distance"));
    EXPECT_GT(passive, 0.05);
    EXPECT_NEAR(std::stod(row.at("ratio")), policy_distance / passive, 1e-3);
  }
  // the passive figure of three objects is srics eval --passive's on them
  const auto [code, passive_output] =
      SricsEval(root, {(root / "run-a").string(), "--passive", "--set", "env.eval_object_sets=[{present: [1, 2, 3]}]",
                       "--episodes", "2", "--no-video", "--out", (root / "passive").string()});
  ASSERT_EQ(code, 0) << passive_output;
  EXPECT_NEAR(std::stod(rows[1].at("passive_object_distance")),
              MeanOf(ReadCsv(root / "passive/episodes.csv"), "avg_object_distance"), 1e-4);
  const std::string table = files::testing::ReadFile(out / "seen-unseen.md");
  EXPECT_THAT(table, HasSubstr("| run-a | 1 2 3 | unseen |"));
  EXPECT_THAT(table, HasSubstr("mean ± sd over 1 runs"));
}

// The same policy under SMORL's protocol (every entity, the static puck 1 too, random order:
// 4 random attempts then all 5, 9 per episode) and, as a method without a graph, under the depth
// protocol of the table's graph by construction (puck 1 has no subgoal: 8 per episode, the arm
// last), on the goals of another seed.
TEST_F(CommittedPolicyTest, PlaysUnderEitherProtocolOnAnotherSeedsGoals) {
  const fs::path policy = Policy();
  const fs::path out = Scratch("protocols");
  const std::vector<std::string> common = {(policy / "policy.srics").string(),
                                           "--config",
                                           (policy / "config.yaml").string(),
                                           "--episodes",
                                           "3",
                                           "--no-video"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = common;
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  auto [code, output] = SricsEval(out, with({"--graph", (policy / "graph.json").string(), "--protocol", "random",
                                             "--goal-set", "2", "--out", (out / "random").string()}));
  ASSERT_EQ(code, 0) << output;
  EXPECT_THAT(output, ::testing::HasSubstr("subgoal order random, goals of evaluation seed 2")) << output;
  auto attempts = ReadCsv(out / "random" / "attempts.csv");
  ASSERT_LE(attempts.size(), 3u * 9u) << output;  // 9 slots, fewer if an episode ends early
  ASSERT_GT(attempts.size(), 3u * 5u) << output;
  int static_puck = 0;
  for (const auto& a : attempts) static_puck += a.at("entity") == "1" ? 1 : 0;
  EXPECT_GT(static_puck, 0) << "every entity is a subgoal under the random protocol";
  const auto episodes_seed2 = ReadCsv(out / "random" / "episodes.csv");
  ASSERT_EQ(episodes_seed2.size(), 3u);
  EXPECT_EQ(episodes_seed2[0].at("seed"), std::to_string(rl::EvalEpisodeSeed(2, 0)));

  std::tie(code, output) =
      SricsEval(out, with({"--set", "run.method=srics_no_selectivity_no_order", "--protocol", "depth", "--graph",
                           (out / "no-such-graph.json").string(), "--out", (out / "depth").string()}));
  EXPECT_EQ(code, 2) << output;  // a --graph that does not exist
  std::tie(code, output) =
      SricsEval(out, with({"--set", "run.method=smorl", "--protocol", "depth", "--out", (out / "depth").string()}));
  ASSERT_EQ(code, 0) << output;
  EXPECT_THAT(output, ::testing::HasSubstr("the table's graph by construction")) << output;
  attempts = ReadCsv(out / "depth" / "attempts.csv");
  // the reference schedule: at most 9 attempts on 4 objects, never the static puck, the arm
  // last in the ordered phase when the episode gets there
  std::map<std::string, std::vector<std::map<std::string, std::string>>> depth_episodes;
  for (const auto& a : attempts) depth_episodes[a.at("episode")].push_back(a);
  ASSERT_EQ(depth_episodes.size(), 3u) << output;
  for (const auto& [episode, list] : depth_episodes) {
    ASSERT_LE(list.size(), 9u) << episode;
    for (const auto& a : list) EXPECT_NE(a.at("entity"), "1");
    if (list.size() == 9u) EXPECT_EQ(list.back().at("entity"), "0") << "the arm is attempted last";
  }

  std::tie(code, output) = SricsEval(out, with({"--protocol", "sideways"}));
  EXPECT_EQ(code, 2) << output;
  EXPECT_THAT(output, ::testing::HasSubstr("--protocol")) << output;
}

class EvalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    run_ = fs::path(SRICS_BINARY_DIR) / "test-data" / "eval_test_run";
    ASSERT_EQ(MakeOrReuseTinyRun(run_), kExitDone) << "the tiny run failed";
  }
  fs::path run() const { return run_; }

  files::testing::ScratchFolder root_{"srics_eval_test"};
  fs::path run_;
};

TEST_F(EvalTest, WritesMetricsAndAVideoOfEveryStep) {
  if (!env::FfmpegAvailable()) GTEST_SKIP() << "ffmpeg is not installed (deploy/install-deps.sh video)";
  const fs::path out = root_ / "eval-mp4";
  const auto [code, output] = SricsEval(root_, {run().string(), "--episodes", "2", "--out", out.string()});
  ASSERT_EQ(code, 0) << output;
  EXPECT_THAT(output, HasSubstr("graph action->0"));
  const auto rows = ReadCsv(out / "episodes.csv");
  ASSERT_EQ(rows.size(), 2u) << ReadFile(out / "episodes.csv");
  for (const auto& row : rows) {
    SCOPED_TRACE("episode " + row.at("episode"));
    ASSERT_EQ(row.at("status"), "ok");
    for (const char* column : {"avg_distance", "avg_object_distance", "distance_0", "distance_1", "success",
                               "subgoal_success_0", "subgoal_success_1"})
      ASSERT_TRUE(row.count(column)) << column;
    // the average of the per-entity distances (arm and one puck)
    EXPECT_NEAR(std::stod(row.at("avg_distance")),
                (std::stod(row.at("distance_0")) + std::stod(row.at("distance_1"))) / 2, 1e-5);
    EXPECT_EQ(row.at("subgoal_success_1"), std::stod(row.at("distance_1")) < 0.05 ? "1" : "0");
    // the protocol: at most 2N - 1 = 3 attempts of 20 steps
    const int steps = std::stoi(row.at("steps"));
    EXPECT_GT(steps, 0);
    EXPECT_LE(steps, 60);
    EXPECT_EQ(std::stoi(row.at("frames")), steps + 1);

    // the video, decoded: one frame per state, a picture in each, and a moving hand
    const fs::path video = out / row.at("video");
    ASSERT_EQ(video.extension(), ".mp4");
    const auto frames = DecodeVideo(video.string(), 640, 480, (root_ / "frames.rgb").string());
    ASSERT_EQ(static_cast<int>(frames.size()), steps + 1);
    EXPECT_GT(PixelStdDev(frames.front()), 20) << "blank first frame";
    EXPECT_GT(PixelStdDev(frames.back()), 20) << "blank last frame";
    EXPECT_GT(DifferingPixels(frames.front(), frames.back()), 50) << "the first and last frames are the same";
    const auto start = FindHand(frames.front());
    ASSERT_TRUE(start.has_value()) << "no hand in the first frame";
    double farthest = 0;
    for (const auto& frame : frames)
      if (const auto hand = FindHand(frame))
        farthest = std::max(farthest, std::hypot(hand->x - start->x, hand->y - start->y));
    EXPECT_GT(farthest, 10) << "the hand never moved in the video";
  }
}

// `srics eval --cross-protocol` on the tiny run: both protocols on two goal sets, the CSV rows and the
// tables; the depth protocol's means equal those of `srics eval --protocol depth` itself.
TEST_F(EvalTest, CrossProtocolStudyPlaysBothProtocolsOnEachGoalSet) {
  const fs::path out = root_ / "cross";
  const auto [study_code, output] = SricsEval(
      root_, {"--cross-protocol", "--goal-sets", "3,4", "--episodes", "2", "--out", out.string(), run().string()});
  ASSERT_EQ(study_code, 0) << output;
  const auto rows = ReadCsv(out / "cross-eval.csv");
  ASSERT_EQ(rows.size(), 4u) << output;
  EXPECT_EQ(rows[0].at("protocol"), "depth");
  EXPECT_EQ(rows[0].at("goal_set"), "3");
  EXPECT_EQ(rows[3].at("protocol"), "random");
  EXPECT_EQ(rows[3].at("goal_set"), "4");
  for (const auto& r : rows) EXPECT_EQ(r.at("episodes"), "2");
  const auto [code, direct] = SricsEval(root_, {run().string(), "--protocol", "depth", "--goal-set", "3", "--episodes",
                                                "2", "--no-video", "--out", (root_ / "direct").string()});
  ASSERT_EQ(code, 0) << direct;
  const auto episodes = ReadCsv(root_ / "direct" / "episodes.csv");
  ASSERT_EQ(episodes.size(), 2u);
  const double mean = (std::stod(episodes[0].at("avg_distance")) + std::stod(episodes[1].at("avg_distance"))) / 2;
  EXPECT_NEAR(std::stod(rows[0].at("avg_distance")), mean, 1e-4);
  const std::string table = files::testing::ReadFile(out / "cross-eval.md");
  EXPECT_THAT(table, HasSubstr("| eval_test_run | srics | depth |")) << table;
  EXPECT_THAT(table, HasSubstr("| srics | random | 1 |")) << table;

  // a folder without a checkpoint: exit 2, naming it, before anything is played
  const auto [bad_code, bad_output] =
      SricsEval(root_, {"--cross-protocol", "--out", (root_ / "cross-bad").string(), run().string(), root_.string()});
  EXPECT_EQ(bad_code, 2);
  EXPECT_THAT(bad_output, HasSubstr("has no checkpoint.srics"));
  EXPECT_FALSE(fs::exists(root_ / "cross-bad" / "raw" / "eval_test_run-depth-goals1")) << "played before the check";
  // several run folders without a study: refused
  const auto [several_code, several_output] = SricsEval(root_, {run().string(), run().string(), "--no-video"});
  EXPECT_EQ(several_code, 2);
  EXPECT_THAT(several_output, HasSubstr("several RUN_DIRs are a study"));
}

TEST_F(EvalTest, PngFramesWithoutFfmpegAndTheSameMetrics) {
  const fs::path out = root_ / "eval-png";
  const auto [code, output] =
      SricsEval(root_, {run().string(), "--episodes", "1", "--out", out.string(), "--format", "png"});
  ASSERT_EQ(code, 0) << output;
  const auto rows = ReadCsv(out / "episodes.csv");
  ASSERT_EQ(rows.size(), 1u);
  const int steps = std::stoi(rows[0].at("steps"));
  const fs::path frames = out / rows[0].at("video");
  ASSERT_TRUE(fs::is_directory(frames)) << frames;
  int count = 0;
  for (const auto& entry : fs::directory_iterator(frames)) count += entry.path().extension() == ".png";
  EXPECT_EQ(count, steps + 1);
  const auto first = ReadPng((frames / "frame-00000.png").string());
  char last_name[32];
  std::snprintf(last_name, sizeof(last_name), "frame-%05d.png", steps);
  const auto last = ReadPng((frames / last_name).string());
  ASSERT_TRUE(first && last);
  EXPECT_GT(DifferingPixels(*first, *last), 50);
  // the same episode as the first of the MP4 evaluation (the protocol's seeds)
  const fs::path other = root_ / "eval-metrics-only";
  ASSERT_EQ(SricsEval(root_, {run().string(), "--episodes", "1", "--out", other.string(), "--no-video"}).first, 0);
  const auto again = ReadCsv(other / "episodes.csv");
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].at("avg_distance"), rows[0].at("avg_distance"));
  EXPECT_EQ(again[0].at("steps"), rows[0].at("steps"));
  EXPECT_EQ(again[0].at("frames"), "0");
}

TEST_F(EvalTest, BadArgumentsExitTwoNamingTheArgument) {
  const std::string dir = run().string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{}, "RUN_DIR|CHECKPOINT"},
      {{(root_ / "nowhere").string()}, "RUN_DIR|CHECKPOINT"},
      {{dir, "--episodes", "0"}, "--episodes"},
      {{dir, "--episodes", "three"}, "--episodes"},
      {{dir, "--format", "avi"}, "--format"},
      {{dir, "--width", "641"}, "--width"},
      {{dir, "--fps"}, "--fps"},
      {{dir, "--frobnicate", "1"}, "--frobnicate"},
      {{dir, "--config", (root_ / "none.yaml").string()}, "--config"},
      {{dir, "--set", "run.method=dqn"}, "run.method"},
  };
  for (const auto& [args, named] : cases) {
    const auto [code, output] = SricsEval(root_, args);
    EXPECT_EQ(code, 2) << output;
    EXPECT_THAT(output, HasSubstr(named));
  }
}

TEST_F(EvalTest, MissingOrCorruptCheckpointSaysSo) {
  // a run folder that has not checkpointed yet
  const fs::path empty = root_ / "no-checkpoint";
  fs::create_directories(empty);
  fs::copy_file(run() / "config.yaml", empty / "config.yaml");
  auto [code, output] = SricsEval(root_, {empty.string(), "--no-video"});
  EXPECT_EQ(code, 1) << output;
  EXPECT_THAT(output, HasSubstr("no checkpoint"));
  EXPECT_THAT(output, HasSubstr((empty / "checkpoint.srics").string()));

  // a truncated checkpoint, given as a file
  const fs::path broken = root_ / "broken";
  fs::create_directories(broken);
  fs::copy_file(run() / "config.yaml", broken / "config.yaml");
  fs::copy_file(run() / "graph.json", broken / "graph.json");
  const std::string bytes = ReadFile(run() / "checkpoint.srics");
  std::ofstream(broken / "checkpoint.srics", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  std::tie(code, output) = SricsEval(root_, {(broken / "checkpoint.srics").string(), "--no-video"});
  EXPECT_EQ(code, 1) << output;
  EXPECT_THAT(output, HasSubstr((broken / "checkpoint.srics").string()));
  EXPECT_THAT(output, HasSubstr("truncated"));

  // not a checkpoint at all
  std::ofstream(broken / "checkpoint.srics", std::ios::binary | std::ios::trunc) << "hello";
  std::tie(code, output) = SricsEval(root_, {broken.string(), "--no-video"});
  EXPECT_EQ(code, 1) << output;
  EXPECT_THAT(output, HasSubstr("checkpoint.srics"));

  // SRICS without its graph
  fs::remove(broken / "graph.json");
  fs::copy_file(run() / "checkpoint.srics", broken / "checkpoint.srics", fs::copy_options::overwrite_existing);
  std::tie(code, output) = SricsEval(root_, {broken.string(), "--no-video"});
  EXPECT_EQ(code, 1) << output;
  EXPECT_THAT(output, HasSubstr("no graph"));
}

}  // namespace
}  // namespace srics::launcher
