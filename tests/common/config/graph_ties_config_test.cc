// graph.object_ties (issue 35, ties as SRICS can use them): two_way, the default, leaves every
// existing config's resolved settings as they were (the key is recorded only when given);
// one_way is recorded, and refused beside a graph that is not learned; joint (the pair as one
// subgoal) is recorded and takes any graph.

#include <gtest/gtest.h>

#include "common/config/config.h"

namespace srics::config {
namespace {

std::string Configs() { return std::string(SRICS_SOURCE_DIR) + "/deploy/configs/"; }

TEST(GraphTiesConfigTest, TwoWayByDefaultAndNotRecordedUnlessGiven) {
  const Config plain = LoadConfig(Configs() + "relational-4.yaml");
  EXPECT_EQ(plain.graph.object_ties, ObjectTies::kTwoWay);
  EXPECT_EQ(plain.resolved_yaml.find("object_ties"), std::string::npos) << plain.resolved_yaml;
  const Config one_way = LoadConfig(Configs() + "relational-4.yaml", {"graph.object_ties=one_way"});
  EXPECT_EQ(one_way.graph.object_ties, ObjectTies::kOneWay);
  EXPECT_NE(one_way.resolved_yaml.find("object_ties: one_way"), std::string::npos) << one_way.resolved_yaml;
  EXPECT_EQ(LoadConfig(Configs() + "relational-4.yaml", {"graph.object_ties=two_way"}).graph.object_ties,
            ObjectTies::kTwoWay);
}

TEST(GraphTiesConfigTest, JointIsRecordedAndTakesAGivenGraph) {
  const Config joint =
      LoadConfig(Configs() + "relational-4.yaml", {"graph.object_ties=joint", "graph.file=graph.json"});
  EXPECT_EQ(joint.graph.object_ties, ObjectTies::kJoint);
  EXPECT_NE(joint.resolved_yaml.find("object_ties: joint"), std::string::npos) << joint.resolved_yaml;
}

TEST(GraphTiesConfigTest, UnknownFormsAndGivenGraphsAreRefused) {
  try {
    LoadConfig(Configs() + "relational-4.yaml", {"graph.object_ties=both"});
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("graph.object_ties"), std::string::npos) << e.what();
  }
  for (const std::string given : {"graph.ground_truth=true", "graph.file=graph.json"}) {
    try {
      LoadConfig(Configs() + "relational-4.yaml", {"graph.object_ties=one_way", given});
      FAIL() << given << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("graph.object_ties: one_way orients a learned graph's ties"),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace srics::config
