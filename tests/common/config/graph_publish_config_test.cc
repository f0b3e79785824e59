// graph.publish (issue 35): which evaluation's graph the service publishes. The lowest held-out
// loss by default since 2026-12-07 and always recorded; last when given; anything else refused
// naming the key.

#include <gtest/gtest.h>

#include "common/config/config.h"
#include "tests/common/config/config_files.h"

namespace srics::config {
namespace {

std::string Configs() { return std::string(SRICS_SOURCE_DIR) + "/deploy/configs/"; }

TEST(GraphPublishConfigTest, LowestLossByDefaultLastWhenGivenOthersRefused) {
  const Config plain = LoadConfig(Configs() + "env/relational-2.yaml");
  EXPECT_EQ(plain.graph.publish, GraphPublish::kLowestHeldOutLoss);
  EXPECT_NE(plain.resolved_yaml.find("publish: lowest_held_out_loss"), std::string::npos) << plain.resolved_yaml;
  const Config last = LoadConfig(Configs() + "env/relational-2.yaml", {"graph.publish=last"});
  EXPECT_EQ(last.graph.publish, GraphPublish::kLast);
  EXPECT_NE(last.resolved_yaml.find("publish: last"), std::string::npos) << last.resolved_yaml;
  try {
    LoadConfig(Configs() + "env/relational-2.yaml", {"graph.publish=best"});
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("graph.publish"), std::string::npos) << e.what();
  }
}

// graph.tie_evidence_per_episode, graph.tie_kl_factor and graph.tie_evidence_share (issue 35):
// on by default since 2026-12-07 (0.025, 0.5; the share 0.5) and always recorded; given values
// recorded; a factor outside (0, 1] or a share outside [0, 1] refused naming the key.
TEST(GraphPublishConfigTest, TieKlSettingsOnByDefaultRecordedBoundsChecked) {
  const Config plain = LoadConfig(Configs() + "env/relational-2.yaml");
  EXPECT_EQ(plain.graph.tie_evidence_per_episode, 0.025);
  EXPECT_EQ(plain.graph.tie_kl_factor, 0.5);
  EXPECT_EQ(plain.graph.tie_evidence_share, 0.5);
  EXPECT_NE(plain.resolved_yaml.find("tie_evidence_per_episode: 0.025"), std::string::npos) << plain.resolved_yaml;
  EXPECT_NE(plain.resolved_yaml.find("tie_kl_factor: 0.5"), std::string::npos) << plain.resolved_yaml;
  const Config given =
      LoadConfig(Configs() + "env/relational-2.yaml",
                 {"graph.tie_evidence_per_episode=0", "graph.tie_kl_factor=1", "graph.tie_evidence_share=0.75"});
  EXPECT_EQ(given.graph.tie_evidence_per_episode, 0);
  EXPECT_EQ(given.graph.tie_kl_factor, 1);
  EXPECT_NE(given.resolved_yaml.find("tie_evidence_per_episode: 0\n"), std::string::npos) << given.resolved_yaml;
  EXPECT_NE(given.resolved_yaml.find("tie_kl_factor: 1\n"), std::string::npos) << given.resolved_yaml;
  EXPECT_EQ(given.graph.tie_evidence_share, 0.75);
  EXPECT_NE(given.resolved_yaml.find("tie_evidence_share: 0.75"), std::string::npos) << given.resolved_yaml;
  for (const std::string bad : {"graph.tie_kl_factor=0", "graph.tie_kl_factor=1.5", "graph.tie_evidence_share=1.5"}) {
    try {
      LoadConfig(Configs() + "env/relational-2.yaml", {bad});
      FAIL() << "accepted " << bad;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(bad.substr(0, bad.find('='))), std::string::npos) << e.what();
    }
  }
}

// graph.tied_pair_threshold and graph.untied_pair_threshold (issue 35): on by default (0.02,
// 0.12) and always recorded; both 0 turns them off; one without the other, or a tied bar above
// the untied one, is refused naming the key; a record without them ran with them off.
TEST(GraphPublishConfigTest, PairBarsOnByDefaultBothOrNeitherTiedNotAboveUntied) {
  const Config plain = LoadConfig(Configs() + "env/relational-2.yaml");
  EXPECT_EQ(plain.graph.tied_pair_threshold, 0.02);
  EXPECT_EQ(plain.graph.untied_pair_threshold, 0.12);
  EXPECT_NE(plain.resolved_yaml.find("tied_pair_threshold: 0.02\n"), std::string::npos) << plain.resolved_yaml;
  EXPECT_NE(plain.resolved_yaml.find("untied_pair_threshold: 0.12\n"), std::string::npos) << plain.resolved_yaml;
  const Config off =
      LoadConfig(Configs() + "env/relational-2.yaml", {"graph.tied_pair_threshold=0", "graph.untied_pair_threshold=0"});
  EXPECT_EQ(off.graph.tied_pair_threshold, 0);
  EXPECT_EQ(off.graph.untied_pair_threshold, 0);
  for (const std::vector<std::string> bad :
       std::vector<std::vector<std::string>>{{"graph.tied_pair_threshold=0"},
                                             {"graph.untied_pair_threshold=0"},
                                             {"graph.tied_pair_threshold=0.2"},
                                             {"graph.untied_pair_threshold=1.5"}}) {
    try {
      LoadConfig(Configs() + "env/relational-2.yaml", bad);
      FAIL() << "accepted " << bad[0];
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("pair_threshold"), std::string::npos) << e.what();
    }
  }
  // each pair's score is scaled by threshold / its bar: a threshold of 0 only with the bars off
  try {
    LoadConfig(Configs() + "env/relational-2.yaml", {"graph.threshold=0"});
    FAIL() << "accepted graph.threshold=0 with the bars";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("graph.threshold"), std::string::npos) << e.what();
  }
  EXPECT_EQ(LoadConfig(Configs() + "env/relational-2.yaml",
                       {"graph.threshold=0", "graph.tied_pair_threshold=0", "graph.untied_pair_threshold=0"})
                .graph.threshold,
            0);
  const std::string old =
      testing::WithoutRecordedKeys(plain.resolved_yaml, {"tied_pair_threshold", "untied_pair_threshold"});
  EXPECT_EQ(EarlierDefaultsOf(old, "record"),
            (std::vector<std::string>{"graph.tied_pair_threshold=0", "graph.untied_pair_threshold=0"}));
  const Config recorded = ParseRecordedConfig(old, "record");
  EXPECT_EQ(recorded.graph.tied_pair_threshold, 0);
  EXPECT_EQ(recorded.graph.untied_pair_threshold, 0);
}

// A record written before the tie KL was the default (resolved-config.yaml without its keys) ran
// with it off: EarlierDefaultsOf gives those overrides and ParseRecordedConfig applies them; a
// record with the keys gets none. Text that is not a mapping is refused naming the record.
TEST(EarlierDefaultsTest, ARecordWithoutTheKeysRanWithTheEarlierDefaults) {
  const Config now = LoadConfig(Configs() + "env/relational-2.yaml");
  EXPECT_TRUE(EarlierDefaultsOf(now.resolved_yaml, "record").empty());
  const std::string old =
      testing::WithoutRecordedKeys(now.resolved_yaml, {"tie_evidence_per_episode", "tie_kl_factor", "publish"});
  EXPECT_EQ(
      EarlierDefaultsOf(old, "record"),
      (std::vector<std::string>{"graph.tie_evidence_per_episode=0", "graph.tie_kl_factor=1", "graph.publish=last"}));
  const Config recorded = ParseRecordedConfig(old, "record");
  EXPECT_EQ(recorded.graph.tie_evidence_per_episode, 0);
  EXPECT_EQ(recorded.graph.tie_kl_factor, 1);
  EXPECT_EQ(recorded.graph.publish, GraphPublish::kLast);
  EXPECT_EQ(ParseConfig(old, "record").graph.tie_evidence_per_episode, 0.025);  // what a plain parse says
  EXPECT_EQ(EarlierDefaultsOf("{}", "record").size(), EarlierDefaults().size());
  try {
    EarlierDefaultsOf("- a list", "run/resolved-config.yaml");
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("run/resolved-config.yaml"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace srics::config
