// A run with a given graph: SeedGraphFile writes it into the run folder as graph.json, which
// the graph service then re-publishes instead of learning.

#include "deploy/launcher/run_folder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "common/graph_file/graph_file.h"
#include "common/rl/ground_truth.h"
#include "tests/common/config/config_files.h"
#include "tests/common/files/test_files.h"

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

// The campaign's runs go on across upgrades (a run folder resumes only if its resolved settings
// are unchanged): the committed folders of the latest campaign runs resolve, on this binary, to
// the settings they recorded. A setting added without "recorded only when given" fails here
// (learner.precision did: every older folder read 'precision: fp32' where it had none). A
// deliberate change of a default fails too: then choose newer folders.
TEST(ConfigChangeSinceTest, TheCampaignsCommittedRunFoldersResolveToTheSettingsTheyRecorded) {
  const fs::path raw = fs::path(SRICS_SOURCE_DIR) / "docs/results/campaign/raw";
  int checked = 0;
  for (const char* group : {"relational-4-750k", "relational-4-ties"}) {
    for (const auto& entry : fs::directory_iterator(raw / group)) {
      const fs::path folder = entry.path();
      if (!fs::exists(folder / "config.yaml") || !fs::exists(folder / "resolved-config.yaml")) continue;
      // as srics run loads a continued run: the defaults it started with (run_folder.h)
      const config::Config config =
          config::LoadConfig((folder / "config.yaml").string(), WithEarlierDefaults(folder.string(), {}));
      EXPECT_EQ(ConfigChangeSince(folder.string(), config.effective_yaml, config.resolved_yaml), "") << folder;
      ++checked;
    }
  }
  EXPECT_GE(checked, 20);
}

TEST(SeedGraphFileTest, GroundTruthIsAValidGraphFileWithTheConfigsEdges) {
  const std::string dir = FreshDir("seed_ground_truth");
  const config::Config config = Load("relational-4.yaml", {"graph.ground_truth=true"});
  SeedGraphFile(config, dir);
  // the graph service loads it (LoadGraph validates everything a saved graph must hold)
  const auto loaded = graph_file::LoadGraph(dir + "/graph.json");
  EXPECT_EQ(loaded.graph.adjacency, rl::GroundTruthGraph(config.env).adjacency);
  EXPECT_EQ(rl::DescribeGraph(loaded.graph), "action->0, 0->2, 0->3, 0->4, 2->3, 3->2");
  EXPECT_EQ(loaded.version, 1u);
}

TEST(SeedGraphFileTest, AGivenFileIsCopiedAndAnExistingGraphIsKept) {
  const std::string source = FreshDir("seed_source");
  SeedGraphFile(Load("rearrange-3.yaml", {"graph.ground_truth=true"}), source);
  const std::string dir = FreshDir("seed_file");
  SeedGraphFile(Load("rearrange-3.yaml", {"graph.file=" + source + "/graph.json"}), dir);
  EXPECT_EQ(graph_file::LoadGraph(dir + "/graph.json").mean_weights,
            graph_file::LoadGraph(source + "/graph.json").mean_weights);
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

// A continued run keeps its configuration (issue 16): the folder's config.yaml is compared
// with the new launch's effective configuration.
TEST(CheckResumedConfigTest, ANewFolderAndTheSameConfigPass) {
  const std::string dir = FreshDir("resume_same");
  const config::Config config = Load("campaign/relational-4.yaml", {"run.seed=2"});
  EXPECT_NO_THROW(CheckResumedConfig(config, dir, false));  // no config.yaml yet
  EXPECT_EQ(PrepareRunFolder(config, dir), fs::absolute(dir).lexically_normal().string());
  EXPECT_NO_THROW(CheckResumedConfig(Load("campaign/relational-4.yaml", {"run.seed=2"}), dir, false));
  // resuming from the folder's own config.yaml is the same configuration
  EXPECT_NO_THROW(CheckResumedConfig(config::LoadConfig(dir + "/config.yaml"), dir, false));
  EXPECT_FALSE(fs::exists(dir + "/config-changes.log"));
}

TEST(CheckResumedConfigTest, AChangedConfigIsRefusedNamingTheChange) {
  const std::string dir = FreshDir("resume_changed");
  PrepareRunFolder(Load("campaign/relational-4.yaml", {"run.seed=2"}), dir);
  const std::string before = WithoutComments(dir + "/config.yaml");
  try {
    CheckResumedConfig(Load("campaign/relational-4.yaml", {"run.seed=3"}), dir, false);
    FAIL() << "a changed seed was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("seed: 2' now '  seed: 3'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--allow-config-change"), std::string::npos) << e.what();
  }
  EXPECT_EQ(WithoutComments(dir + "/config.yaml"), before);  // nothing written
}

TEST(CheckResumedConfigTest, AnAllowedChangeKeepsTheOldFileAndRecordsTheChange) {
  const std::string dir = FreshDir("resume_allowed");
  PrepareRunFolder(Load("campaign/relational-4.yaml", {"run.seed=2"}), dir);
  const std::string before = WithoutComments(dir + "/config.yaml");
  const config::Config changed = Load("campaign/relational-4.yaml", {"run.seed=3"});
  CheckResumedConfig(changed, dir, true);
  std::ifstream log(dir + "/config-changes.log");
  std::string line;
  ASSERT_TRUE(std::getline(log, line));
  EXPECT_NE(line.find("seed: 2' now '  seed: 3'"), std::string::npos) << line;
  const std::string kept = line.substr(line.find("config.yaml."), std::string("config.yaml.20261202T004500Z").size());
  EXPECT_EQ(WithoutComments(dir + "/" + kept), before) << kept;
  PrepareRunFolder(changed, dir);  // then the launch writes the new one
  EXPECT_NO_THROW(CheckResumedConfig(changed, dir, false));
}

// Since 2026-12-03 a folder records every resolved setting (resolved-config.yaml), and a
// continued run is compared on those: a key pinned to the value it had is no change, and a
// default that changed between binaries is one (here the folder's record says the binary that
// started the run had the reference code's selectivity form as its default).
TEST(CheckResumedConfigTest, TheResolvedSettingsDecide) {
  const std::string dir = FreshDir("resume_resolved");
  const config::Config started = Load("rearrange-3.yaml", {"run.seed=2"});
  PrepareRunFolder(started, dir);
  ASSERT_TRUE(fs::exists(dir + "/resolved-config.yaml"));
  const config::Config pinned = Load("rearrange-3.yaml", {"run.seed=2", "agent.reward.selectivity_form=paper"});
  ASSERT_NE(pinned.effective_yaml, started.effective_yaml);
  EXPECT_NO_THROW(CheckResumedConfig(pinned, dir, false));
  // the record of a binary whose default was the reference form
  std::string record = files::testing::ReadFile(dir + "/resolved-config.yaml");
  const size_t at = record.find("selectivity_form: paper");
  ASSERT_NE(at, std::string::npos) << record;
  record.replace(at, std::string("selectivity_form: paper").size(), "selectivity_form: reference");
  std::ofstream(dir + "/resolved-config.yaml") << record;
  try {
    CheckResumedConfig(started, dir, false);
    FAIL() << "a changed default was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("selectivity_form: reference' now '    selectivity_form: paper'"),
              std::string::npos)
        << e.what();
  }
  // a folder from before the record: its merged YAML decides (the pin is then a change)
  fs::remove(dir + "/resolved-config.yaml");
  EXPECT_NO_THROW(CheckResumedConfig(started, dir, false));
  EXPECT_THROW(CheckResumedConfig(pinned, dir, false), std::invalid_argument);
}

// A run started before a default changed (its record lacks the key: config::EarlierDefaults)
// goes on with the value it had: srics run loads it with WithEarlierDefaults and the check passes,
// where a plain load would hand it the new default unseen (it did: the record, re-resolved, took
// the new default too). Given overrides still win, and are then a change.
TEST(CheckResumedConfigTest, ARunFromBeforeADefaultChangedKeepsItsValue) {
  const std::string dir = FreshDir("resume_earlier_default");
  const std::string file = std::string(SRICS_SOURCE_DIR) + "/deploy/configs/env/relational-2.yaml";
  PrepareRunFolder(config::LoadConfig(file), dir);
  const std::string record = files::testing::ReadFile(dir + "/resolved-config.yaml");
  std::ofstream(dir + "/resolved-config.yaml")
      << config::testing::WithoutRecordedKeys(record, {"tie_evidence_per_episode", "tie_kl_factor"});
  const config::Config resumed = config::LoadConfig(file, WithEarlierDefaults(dir, {}));
  EXPECT_EQ(resumed.graph.tie_evidence_per_episode, 0);
  EXPECT_EQ(resumed.graph.tie_kl_factor, 1);
  EXPECT_NO_THROW(CheckResumedConfig(resumed, dir, false));
  try {
    CheckResumedConfig(config::LoadConfig(file), dir, false);
    FAIL() << "the new default was handed to a run that started without it";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tie_"), std::string::npos) << e.what();
  }
  const config::Config asked = config::LoadConfig(file, WithEarlierDefaults(dir, {"graph.tie_kl_factor=0.5"}));
  EXPECT_EQ(asked.graph.tie_kl_factor, 0.5);
  EXPECT_THROW(CheckResumedConfig(asked, dir, false), std::invalid_argument);
  // a folder without a record (a new run): the overrides as given
  EXPECT_EQ(WithEarlierDefaults(FreshDir("resume_no_record"), {"run.seed=2"}), std::vector<std::string>{"run.seed=2"});
}

}  // namespace
}  // namespace srics::launcher
