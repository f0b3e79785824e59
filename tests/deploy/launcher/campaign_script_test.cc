// deploy/campaign.sh, the campaign's queue, in --dry-run: which runs it skips (their curves are
// in docs/results/campaign/raw/ with a finished outcome), the sweep it would start for the
// others, and the exit code 2 naming the line for a malformed queue or a missing config.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Output {
  int exit_code = -1;
  std::string text;  // stdout and stderr
};

Output RunQueue(const std::string& queue_text) {
  const fs::path dir = fs::temp_directory_path() / ("campaign_script_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path queue = dir / "queue.txt";
  std::ofstream(queue) << queue_text;
  const std::string command = std::string(SRICS_SOURCE_DIR) + "/deploy/campaign.sh --dry-run --queue " +
                              queue.string() + " 2>&1";
  Output out;
  FILE* pipe = ::popen(command.c_str(), "r");
  char buffer[4096];
  while (size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) out.text.append(buffer, n);
  const int status = ::pclose(pipe);
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  fs::remove_all(dir);
  return out;
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
  EXPECT_NE(out.text.find("srics_no_selectivity-seed2 (relational-4-ablations): finished"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find("sweep deploy/configs/campaign/relational-4.yaml --methods srics --seeds 7 --in-process "
                          "--out runs/campaign/some-folder --set agent.reward.selectivity_form=paper  -> "
                          "docs/results/campaign/raw/relational-4-ablations/srics_paper_selectivity-seed7"),
            std::string::npos)
      << out.text;
  EXPECT_EQ(out.text.find("--methods srics_no_selectivity --seeds 2"), std::string::npos)
      << "a finished run is planned again:\n" << out.text;
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

// the committed queue parses, and every config it names exists
TEST(CampaignScriptTest, TheCommittedQueueIsWellFormed) {
  std::ifstream in(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/campaign/queue.txt");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(text.empty());
  const Output out = RunQueue(text);
  EXPECT_EQ(out.exit_code, 0) << out.text;
}

}  // namespace
