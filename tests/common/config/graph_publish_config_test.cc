// graph.publish (issue 35): which evaluation's graph the service publishes. `last` by default
// and not recorded in the resolved settings unless given (configs written before the key
// resolve as before); lowest_held_out_loss recorded; anything else refused naming the key.

#include <gtest/gtest.h>

#include "common/config/config.h"

namespace srics::config {
namespace {

std::string Configs() { return std::string(SRICS_SOURCE_DIR) + "/deploy/configs/"; }

TEST(GraphPublishConfigTest, LastByDefaultLowestLossWhenGivenOthersRefused) {
  const Config plain = LoadConfig(Configs() + "env/relational-2.yaml");
  EXPECT_EQ(plain.graph.publish, GraphPublish::kLast);
  EXPECT_EQ(plain.resolved_yaml.find(" publish: "), std::string::npos) << plain.resolved_yaml;
  const Config lowest = LoadConfig(Configs() + "env/relational-2.yaml", {"graph.publish=lowest_held_out_loss"});
  EXPECT_EQ(lowest.graph.publish, GraphPublish::kLowestHeldOutLoss);
  EXPECT_NE(lowest.resolved_yaml.find("publish: lowest_held_out_loss"), std::string::npos) << lowest.resolved_yaml;
  try {
    LoadConfig(Configs() + "env/relational-2.yaml", {"graph.publish=best"});
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("graph.publish"), std::string::npos) << e.what();
  }
}

// graph.tie_evidence_per_episode, graph.tie_kl_factor and graph.tie_evidence_share (issue 35):
// off (0 and 1; the share 0.5) and not recorded unless given; recorded when given; a factor
// outside (0, 1] or a share outside [0, 1] refused naming the key.
TEST(GraphPublishConfigTest, TieKlSettingsOffByDefaultRecordedWhenGivenBoundsChecked) {
  const Config plain = LoadConfig(Configs() + "env/relational-2.yaml");
  EXPECT_EQ(plain.graph.tie_evidence_per_episode, 0);
  EXPECT_EQ(plain.graph.tie_kl_factor, 1);
  EXPECT_EQ(plain.graph.tie_evidence_share, 0.5);
  EXPECT_EQ(plain.resolved_yaml.find("tie_"), std::string::npos) << plain.resolved_yaml;
  const Config given =
      LoadConfig(Configs() + "env/relational-2.yaml",
                 {"graph.tie_evidence_per_episode=0.025", "graph.tie_kl_factor=0.5", "graph.tie_evidence_share=0.75"});
  EXPECT_EQ(given.graph.tie_evidence_per_episode, 0.025);
  EXPECT_EQ(given.graph.tie_kl_factor, 0.5);
  EXPECT_NE(given.resolved_yaml.find("tie_evidence_per_episode: 0.025"), std::string::npos) << given.resolved_yaml;
  EXPECT_NE(given.resolved_yaml.find("tie_kl_factor: 0.5"), std::string::npos) << given.resolved_yaml;
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

}  // namespace
}  // namespace srics::config
