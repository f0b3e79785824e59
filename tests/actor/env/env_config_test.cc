// Parsing of the `env` section: presets load, defaults match docs/method.md section 1, and
// every broken rule fails with file:line, key path and expectation.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "actor/env/rearrange_env.h"
#include "common/config/config.h"
#include "tests/actor/env/env_presets.h"

namespace srics::config {
namespace {

using env::testing::PresetPath;

// The ConfigError message of parsing `yaml`, or "" when it parses.
std::string ErrorOf(const std::string& yaml) {
  try {
    ParseConfig(yaml, "test.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

// Expects the ConfigError of parsing `yaml` to contain every one of `parts`.
void ExpectError(const std::string& yaml, std::initializer_list<std::string> parts) {
  const std::string e = ErrorOf(yaml);
  for (const std::string& part : parts) EXPECT_NE(e.find(part), std::string::npos) << e;
}

TEST(EnvConfigTest, DefaultsAreTheReferenceNumbers) {
  const EnvConfig c;
  EXPECT_EQ(c.num_pucks, 3);
  EXPECT_DOUBLE_EQ(c.physics.timestep, 0.002);
  EXPECT_EQ(c.physics.solver_iterations, 50);
  EXPECT_EQ(c.physics.frame_skip, 50);
  EXPECT_DOUBLE_EQ(c.hand.action_scale, 0.1);
  EXPECT_DOUBLE_EQ(c.hand.z, 0.02);
  EXPECT_DOUBLE_EQ(c.hand.mocap_low[1], 0.40);
  EXPECT_DOUBLE_EQ(c.table.object_low[0], -0.24);
  EXPECT_DOUBLE_EQ(c.table.wall_y_high, 0.76);
  EXPECT_DOUBLE_EQ(c.sampling.init_min_object_distance, 0.10);
  EXPECT_DOUBLE_EQ(c.sampling.init_min_hand_distance, 0.06);
  EXPECT_DOUBLE_EQ(c.sampling.goal_min_object_distance, 0.125);
  EXPECT_DOUBLE_EQ(c.sampling.goal_min_hand_distance, 0.075);
  EXPECT_DOUBLE_EQ(c.success_threshold, 0.05);
  const ObjectConfig puck;
  EXPECT_DOUBLE_EQ(puck.size, 0.04);
  EXPECT_DOUBLE_EQ(puck.half_height, 0.015);
  EXPECT_DOUBLE_EQ(puck.mass, 0.1);
  EXPECT_DOUBLE_EQ(puck.inertia, 100000.0);
  EXPECT_DOUBLE_EQ(ConnectionConfig().length, 0.13);
  EXPECT_TRUE(CheckEnvConfig(c).ok());
}

TEST(EnvConfigTest, EveryPresetLoadsAndBuildsAnEnvironment) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/env")) {
    SCOPED_TRACE(entry.path().string());
    const Config config = LoadConfig(entry.path().string());
    env::RearrangeEnv environment(config.env);
    EXPECT_GE(environment.layout().num_entities, 2);
    ++count;
  }
  EXPECT_GE(count, 10);
}

// The paper's generalization split: Rearrange 4's pucks, one removed per training episode,
// evaluation on the combination never trained on.
TEST(EnvConfigTest, UnseenPresetTrainsOnThreeCombinationsAndEvaluatesOnTheFourth) {
  const EnvConfig unseen = LoadConfig(PresetPath("rearrange-4-unseen")).env;
  EXPECT_EQ(unseen.num_pucks, 4);
  EXPECT_TRUE(unseen.objects.empty());  // four identical pucks
  EXPECT_EQ(unseen.object_sets, (std::vector<std::vector<int>>{{1, 2, 3}, {1, 2, 4}, {1, 3, 4}}));
  EXPECT_EQ(unseen.eval_object_sets, (std::vector<std::vector<int>>{{2, 3, 4}}));
  env::RearrangeEnv environment(unseen);
  std::set<std::vector<int>> trained;
  for (uint64_t seed = 0; seed < 60; ++seed) {
    environment.Reset(seed, env::Split::kTrain);
    trained.insert(environment.layout().kinds);
    environment.Reset(seed, env::Split::kEval);
    EXPECT_EQ(environment.layout().kinds, (std::vector<int>{0, 2, 3, 4}));
  }
  EXPECT_EQ(trained, (std::set<std::vector<int>>{{0, 1, 2, 3}, {0, 1, 2, 4}, {0, 1, 3, 4}}));
}

TEST(EnvConfigTest, PresetsSayWhatTheirNamesSay) {
  const EnvConfig relational = LoadConfig(PresetPath("relational-4")).env;
  ASSERT_EQ(relational.objects.size(), 4u);
  EXPECT_TRUE(relational.objects[0].is_static);
  EXPECT_FALSE(relational.objects[1].is_static);
  ASSERT_EQ(relational.connections.size(), 1u);
  EXPECT_EQ(relational.connections[0].first, 2);
  EXPECT_EQ(relational.connections[0].second, 3);
  EXPECT_EQ(relational.connections[0].kind, ConnectionKind::kRope);
  EXPECT_DOUBLE_EQ(relational.connections[0].length, 0.13);

  const EnvConfig spring = LoadConfig(PresetPath("relational-4-spring")).env;
  EXPECT_EQ(spring.connections.at(0).kind, ConnectionKind::kSpring);
  EXPECT_TRUE(spring.objects.at(0).is_static);  // inherited through extends

  EXPECT_TRUE(LoadConfig(PresetPath("rearrange-4-velocity")).env.velocities);
  EXPECT_EQ(LoadConfig(PresetPath("rearrange-4-velocity")).env.num_pucks, 4);

  const EnvConfig different = LoadConfig(PresetPath("different-6")).env;
  ASSERT_EQ(different.objects.size(), 6u);
  int boxes = 0;
  for (const auto& o : different.objects) boxes += o.shape == ObjectShape::kBox;
  EXPECT_EQ(boxes, 3);

  const EnvConfig combos = LoadConfig(PresetPath("rearrange-4-combinations")).env;
  EXPECT_EQ(combos.object_sets.size(), 3u);
  ASSERT_EQ(combos.eval_object_sets.size(), 1u);
  EXPECT_EQ(combos.eval_object_sets[0], (std::vector<int>{2, 3, 4}));
  for (const auto& set : combos.object_sets) EXPECT_NE(set, combos.eval_object_sets[0]);
  EXPECT_EQ(LoadConfig(PresetPath("rearrange-4-heldout")).env.object_sets, (std::vector<std::vector<int>>{{2, 3, 4}}));
}

TEST(EnvConfigTest, NegativeMassNamesFileLineAndKey) {
  const std::string e = ErrorOf("env:\n  objects:\n    - {mass: 0.1}\n    - {mass: -0.5}\n");
  EXPECT_NE(e.find("test.yaml:4"), std::string::npos) << e;
  EXPECT_NE(e.find("env.objects[1].mass"), std::string::npos) << e;
  EXPECT_NE(e.find("expected a number"), std::string::npos) << e;
  EXPECT_NE(e.find("-0.5"), std::string::npos) << e;
}

TEST(EnvConfigTest, UnknownShapeListsTheShapes) {
  const std::string e = ErrorOf("env:\n  objects:\n    - {shape: sphere}\n");
  EXPECT_NE(e.find("env.objects[0].shape"), std::string::npos) << e;
  EXPECT_NE(e.find("'cylinder' 'box'"), std::string::npos) << e;
  EXPECT_NE(e.find("sphere"), std::string::npos) << e;
}

TEST(EnvConfigTest, UnknownKeysAreRejectedWithASuggestion) {
  ExpectError("env:\n  num_puck: 3\n", {"env.num_puck: unknown key", "did you mean 'num_pucks'"});
  ExpectError("env:\n  hand:\n    action_scal: 0.1\n", {"env.hand.action_scal: unknown key"});
  ExpectError("env:\n  objects:\n    - {mas: 0.1}\n", {"env.objects[0].mas: unknown key"});
}

TEST(EnvConfigTest, OverlappingFixedObjectsFail) {
  const std::string e = ErrorOf(
      "env:\n  objects:\n    - {static: true, fixed_position: [0.0, 0.6]}\n"
      "    - {static: true, fixed_position: [0.05, 0.6]}\n");
  EXPECT_NE(e.find("test.yaml:4: env.objects[1].fixed_position: overlapping fixed objects: "
                   "entities 1 and 2"),
            std::string::npos)
      << e;
}

TEST(EnvConfigTest, MoreObjectsThanFitTheTableFail) {
  std::string yaml = "env:\n  objects:\n";
  for (int i = 0; i < 6; ++i) yaml += "    - {shape: box, size: 0.09}\n";
  const std::string e = ErrorOf(yaml);
  EXPECT_NE(e.find("env.objects"), std::string::npos) << e;
  EXPECT_NE(e.find("more objects than fit the table"), std::string::npos) << e;
  // one object larger than the table itself
  const std::string huge = ErrorOf("env:\n  objects:\n    - {size: 0.3}\n");
  EXPECT_NE(huge.find("does not fit on the table"), std::string::npos) << huge;
}

TEST(EnvConfigTest, CrowdedTableFailsInTheEnvironmentToo) {
  // passes the density rule but rejection sampling cannot place it: the constructor says so
  EnvConfig c;
  c.objects.assign(6, ObjectConfig{});
  c.sampling.goal_min_object_distance = 0.2;
  c.sampling.max_attempts = 2000;
  try {
    env::RearrangeEnv environment(c);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("more objects than fit the table"), std::string::npos) << e.what();
  }
}

TEST(EnvConfigTest, ConnectionAndObjectSetRules) {
  ExpectError("env:\n  num_pucks: 3\n  connections:\n    - {objects: [2, 5]}\n",
              {"test.yaml:4: env.connections[0].objects: objects are entities 1..3"});
  ExpectError("env:\n  connections:\n    - {objects: [2, 2]}\n", {"tied to itself"});
  ExpectError("env:\n  connections:\n    - {objects: [2, 3], kind: chain}\n",
              {"env.connections[0].kind: expected one of 'rope' 'spring'"});
  ExpectError(
      "env:\n  num_pucks: 4\n  connections:\n    - {objects: [2, 3]}\n"
      "  object_sets:\n    - {present: [1, 2, 4]}\n",
      {"both or neither"});
  ExpectError("env:\n  object_sets:\n    - {present: [1, 1]}\n", {"repeated"});
  // two 6 cm cylinders overlap at a 0.11 m tie's full length
  ExpectError(
      "env:\n  objects:\n    - {size: 0.06}\n    - {size: 0.06}\n  connections:\n"
      "    - {objects: [1, 2], length: 0.11}\n",
      {"env.connections[0].length: must be at least the two objects' bounding radii together (0.12)"});
  ExpectError("env:\n  num_pucks: 2\n  objects:\n    - {}\n", {"env.num_pucks"});
}

TEST(EnvConfigTest, ExtendsAndOverridesMergeIntoEnv) {
  const auto dir = std::filesystem::temp_directory_path() / "srics_env_config_test";
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "run.yaml") << "extends: " << PresetPath("relational-4") << "\nenv:\n  velocities: true\n"; }
  const Config c = LoadConfig((dir / "run.yaml").string(), {"env.hand.action_scale=0.05"});
  EXPECT_TRUE(c.env.velocities);
  EXPECT_EQ(c.env.connections.size(), 1u);
  EXPECT_DOUBLE_EQ(c.env.hand.action_scale, 0.05);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace srics::config
