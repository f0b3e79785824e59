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

}  // namespace
}  // namespace srics::config
