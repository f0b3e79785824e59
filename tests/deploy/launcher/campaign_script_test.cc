// deploy/campaign.sh, the campaign's queue, in --dry-run: which runs it skips (their curves are
// in docs/results/campaign/raw/ with a finished outcome), the sweep it would start for the
// others, the exit code 2 naming the line for a malformed queue or a missing config, and that a
// run another queue is training (its lock held) is skipped, not started twice.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "tests/common/cli/shell_testing.h"

namespace {

namespace fs = std::filesystem;

struct Output {
  int exit_code = -1;
  std::string text;  // stdout and stderr
};

fs::path TestDir() { return fs::temp_directory_path() / ("campaign_script_test_" + std::to_string(::getpid())); }

// runs_dir empty: the script's default (runs/campaign)
Output RunQueue(const std::string& queue_text, const std::string& runs_dir = "", const std::string& options = "") {
  const fs::path dir = TestDir();
  fs::create_directories(dir);
  const fs::path queue = dir / "queue.txt";
  std::ofstream(queue) << queue_text;
  const auto [code, text] =
      srics::cli::testing::Shell(std::string(SRICS_SOURCE_DIR) + "/deploy/campaign.sh --dry-run --queue " +
                                 queue.string() + (runs_dir.empty() ? "" : " --runs " + runs_dir) + " " + options);
  fs::remove_all(dir);
  return {code, text};
}

// Under autogroup scheduling nice ranks processes only within a session: the queue nices its
// whole scheduling group (a run niced to 0 got 56% of its core beside builds niced to 15 in
// other sessions). Run in a session of its own, so that only this test's group is changed.
TEST(CampaignScriptTest, NicesItsSchedulingGroup) {
  if (!fs::exists("/proc/self/autogroup")) GTEST_SKIP() << "no autogroup scheduling in this kernel";
  const fs::path dir = TestDir();
  fs::create_directories(dir);
  std::ofstream(dir / "queue.txt") << "# nothing to run\n";
  const auto [code, text] = srics::cli::testing::Shell(
      "setsid bash -c '" + std::string(SRICS_SOURCE_DIR) + "/deploy/campaign.sh --dry-run --queue " +
      (dir / "queue.txt").string() + " >/dev/null; cat /proc/self/autogroup'");
  fs::remove_all(dir);
  EXPECT_EQ(code, 0) << text;
  EXPECT_NE(text.find(" nice 10"), std::string::npos) << text;
}

// bash reads a script as it runs it: an edit of deploy/campaign.sh while a queue trains (a new
// queue line's comment, a fix) used to break that queue once its loop ended ("syntax error near
// unexpected token"). The script is read whole before it starts. Tested on a copy in a scratch
// tree with a stand-in srics that trains for a second while the copy is edited.
TEST(CampaignScriptTest, AnEditOfTheScriptWhileAQueueRunsDoesNotBreakIt) {
  const fs::path root = TestDir() / "tree";
  fs::create_directories(root / "deploy/configs/campaign");
  fs::create_directories(root / "build/deploy/launcher");
  fs::copy_file(std::string(SRICS_SOURCE_DIR) + "/deploy/campaign.sh", root / "deploy/campaign.sh");
  std::ofstream(root / "deploy/configs/campaign/x.yaml") << "run:\n  name: x\n";
  // the stand-in: `srics sweep CONFIG --methods M --seeds S ... --out DIR` finishes M-seedS after a second
  const fs::path srics = root / "build/deploy/launcher/srics";
  std::ofstream(srics) << "#!/usr/bin/env bash\n"
                          "while [[ $# -gt 0 ]]; do case $1 in --out) out=$2; shift 2;; --methods) m=$2; shift 2;;"
                          " --seeds) s=$2; shift 2;; *) shift;; esac; done\n"
                          "mkdir -p \"$out/$m-seed$s\"; sleep 1\n"
                          "printf 'state: finished\\n' > \"$out/$m-seed$s/outcome.yaml\"\n"
                          "printf 'env_steps\\n1\\n' > \"$out/$m-seed$s/eval.csv\"\n"
                          "printf 'seed: 1\\n' > \"$out/sweep.yaml\"\n";
  fs::permissions(srics, fs::perms::owner_all);
  std::ofstream(root / "queue.txt") << "q1 g srics deploy/configs/campaign/x.yaml srics 1\n";
  const std::string script = (root / "deploy/campaign.sh").string();
  const std::string edit = "sleep 0.5; { printf '# an edit while the queue runs\\n%.0s' $(seq 30); cat " + script +
                           "; } > " + script + ".new && cat " + script + ".new > " +
                           script;  // in place, as an editor writes
  const auto [code, text] = srics::cli::testing::Shell(
      "cd " + root.string() + " && (" + edit + ") & " + script + " --final-episodes 0 --queue " +
      (root / "queue.txt").string() + " --runs " + (root / "runs").string() + " 2>&1; echo exit $?; wait");
  fs::remove_all(TestDir());
  EXPECT_NE(text.find("the queue is done"), std::string::npos) << text;
  EXPECT_EQ(text.find("syntax error"), std::string::npos) << text;
  EXPECT_NE(text.find("exit 0"), std::string::npos) << text;
}

// srics_no_selectivity seed 2 of Relational Rearrange 4 is committed as finished
TEST(CampaignScriptTest, SkipsFinishedRunsAndPlansTheOthers) {
  const Output out = RunQueue(
      "# a comment line\n"
      "\n"
      "relational-4-no-selectivity-seed2 relational-4-ablations srics_no_selectivity "
      "deploy/configs/campaign/relational-4.yaml srics_no_selectivity 2\n"
      "some-folder relational-4-ablations srics_paper_selectivity deploy/configs/campaign/relational-4.yaml "
      "srics 7 --set agent.reward.selectivity_form=paper  # trailing comment\n");
  EXPECT_EQ(out.exit_code, 0) << out.text;
  EXPECT_NE(out.text.find("srics_no_selectivity-seed2 (relational-4-ablations): finished"), std::string::npos)
      << out.text;
  EXPECT_NE(out.text.find("sweep deploy/configs/campaign/relational-4.yaml --methods srics --seeds 7 --in-process "
                          "--out runs/campaign/some-folder --set agent.reward.selectivity_form=paper  -> "
                          "docs/results/campaign/raw/relational-4-ablations/srics_paper_selectivity-seed7"),
            std::string::npos)
      << out.text;
  EXPECT_EQ(out.text.find("--methods srics_no_selectivity --seeds 2"), std::string::npos)
      << "a finished run is planned again:\n"
      << out.text;
}

TEST(CampaignScriptTest, MalformedLinesAndMissingConfigsExitTwoNamingTheLine) {
  Output out = RunQueue("folder group name deploy/configs/campaign/relational-4.yaml srics\n");
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_NE(out.text.find("queue.txt:1: expected OUT GROUP NAME CONFIG METHOD SEED"), std::string::npos) << out.text;
  out = RunQueue("\nfolder group name deploy/configs/campaign/no-such.yaml srics 1\n");
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_NE(out.text.find("queue.txt:2: no config file deploy/configs/campaign/no-such.yaml"), std::string::npos)
      << out.text;
}

// Two queues on two cores: the run one of them trains holds DIR/OUT.lock; the other skips it and
// plans the next run.
TEST(CampaignScriptTest, ARunAnotherQueueIsTrainingIsSkipped) {
  const fs::path runs = fs::temp_directory_path() / ("campaign_script_runs_" + std::to_string(::getpid()));
  fs::create_directories(runs);
  const std::string queue =
      "busy-folder group srics_paper_selectivity deploy/configs/campaign/relational-4.yaml srics 8\n"
      "free-folder group srics_paper_selectivity deploy/configs/campaign/relational-4.yaml srics 9\n";
  const int fd = ::open((runs / "busy-folder.lock").c_str(), O_CREAT | O_RDWR, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  Output out = RunQueue(queue, runs.string());
  EXPECT_EQ(out.exit_code, 0) << out.text;
  EXPECT_NE(out.text.find("srics_paper_selectivity-seed8 (group): being trained by another queue"), std::string::npos)
      << out.text;
  EXPECT_EQ(out.text.find("--seeds 8"), std::string::npos) << "a locked run is planned:\n" << out.text;
  EXPECT_NE(out.text.find("--seeds 9 --in-process --out " + runs.string() + "/free-folder"), std::string::npos)
      << out.text;
  // the lock released (the other queue's sweep ended): the run is planned again
  ::close(fd);
  out = RunQueue(queue, runs.string());
  EXPECT_NE(out.text.find("--seeds 8 --in-process --out " + runs.string() + "/busy-folder"), std::string::npos)
      << out.text;
  fs::remove_all(runs);
}

// A finished run whose raw folder has no final evaluation, its sweep folder still holding the
// last checkpoint, gets one (the run's own goals and the selection goals); --final-eval-only
// trains nothing; a run without its checkpoint is left as it is.
TEST(CampaignScriptTest, FinishedRunsGetTheirFinalEvaluationAndFinalEvalOnlyTrainsNothing) {
  const fs::path runs = fs::temp_directory_path() / ("campaign_script_final_" + std::to_string(::getpid()));
  const fs::path run = runs / "relational-4-no-selectivity-seed2" / "srics_no_selectivity-seed2";
  fs::create_directories(run);
  std::ofstream(run / "checkpoint.srics") << "a checkpoint";
  const std::string queue =
      "relational-4-no-selectivity-seed2 relational-4-ablations srics_no_selectivity "
      "deploy/configs/campaign/relational-4.yaml srics_no_selectivity 2\n"
      "free-folder group srics_paper_selectivity deploy/configs/campaign/relational-4.yaml srics 9\n";
  Output out = RunQueue(queue, runs.string(), "--final-eval-only");
  EXPECT_EQ(out.exit_code, 0) << out.text;
  EXPECT_NE(out.text.find("would evaluate " + run.string() +
                          "'s last checkpoint over 300 episodes -> "
                          "docs/results/campaign/raw/relational-4-ablations/srics_no_selectivity-seed2/final-eval*"),
            std::string::npos)
      << out.text;
  EXPECT_NE(out.text.find("srics_paper_selectivity-seed9 (group): not finished, left alone (--final-eval-only)"),
            std::string::npos)
      << out.text;
  EXPECT_EQ(out.text.find("--seeds 9"), std::string::npos) << "--final-eval-only plans a run:\n" << out.text;

  out = RunQueue(queue, runs.string(), "--final-episodes 0");
  EXPECT_EQ(out.text.find("would evaluate"), std::string::npos) << out.text;
  out = RunQueue(queue, runs.string(), "--final-episodes many");
  EXPECT_EQ(out.exit_code, 2) << out.text;
  EXPECT_NE(out.text.find("--final-episodes takes a count, got 'many'"), std::string::npos) << out.text;

  fs::remove(run / "checkpoint.srics");
  out = RunQueue(queue, runs.string(), "--final-eval-only");
  EXPECT_EQ(out.text.find("would evaluate"), std::string::npos) << "no checkpoint to evaluate:\n" << out.text;
  fs::remove_all(runs);
}

// the committed queue parses, and every config it names exists
TEST(CampaignScriptTest, TheCommittedQueueIsWellFormed) {
  std::ifstream in(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/campaign/queue.txt");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(text.empty());
  const Output out = RunQueue(text);
  EXPECT_EQ(out.exit_code, 0) << out.text;
}

}  // namespace
