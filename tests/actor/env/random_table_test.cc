#include "actor/env/random_table.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "common/config/config.h"
#include "common/rl/ground_truth.h"

namespace srics::env {
namespace {

TEST(RandomTableTest, SameSeedSameTableAndSeedsDiffer) {
  const std::string a = RandomTableYaml(RandomTable(7), 7, "");
  EXPECT_EQ(a, RandomTableYaml(RandomTable(7), 7, ""));
  EXPECT_NE(a, RandomTableYaml(RandomTable(8), 7, ""));
}

// Every draw passes the environment's own rules, ties join two movable objects that take part
// in no other tie, and over many seeds every kind of table occurs.
TEST(RandomTableTest, TablesAreValidAndVaried) {
  std::set<int> counts;
  int statics = 0, ropes = 0, springs = 0, boxes = 0, cylinders = 0, untied = 0;
  for (uint64_t seed = 1; seed <= 200; ++seed) {
    const config::EnvConfig t = RandomTable(seed);
    ASSERT_TRUE(config::CheckEnvConfig(t).ok()) << "seed " << seed;
    const int n = static_cast<int>(t.objects.size());
    ASSERT_GE(n, 2);
    ASSERT_LE(n, 5);
    counts.insert(n);
    int movable = 0;
    for (const auto& o : t.objects) {
      statics += o.is_static;
      movable += !o.is_static;
      boxes += o.shape == config::ObjectShape::kBox;
      cylinders += o.shape == config::ObjectShape::kCylinder;
      EXPECT_GE(o.size, 0.025);
      EXPECT_LE(o.size, 0.045);
    }
    EXPECT_GE(movable, 2) << "seed " << seed;
    std::set<int> tied;
    for (const auto& c : t.connections) {
      EXPECT_FALSE(t.objects[c.first - 1].is_static);
      EXPECT_FALSE(t.objects[c.second - 1].is_static);
      EXPECT_TRUE(tied.insert(c.first).second) << "object in two ties, seed " << seed;
      EXPECT_TRUE(tied.insert(c.second).second) << "object in two ties, seed " << seed;
      (c.kind == config::ConnectionKind::kRope ? ropes : springs) += 1;
    }
    untied += t.connections.empty();
  }
  EXPECT_EQ(counts, (std::set<int>{2, 3, 4, 5}));
  EXPECT_GT(statics, 20);
  EXPECT_GT(ropes, 20);
  EXPECT_GT(springs, 20);
  EXPECT_GT(boxes, 100);
  EXPECT_GT(cylinders, 100);
  EXPECT_GT(untied, 20);
}

// The preset file reads back as the same table through the config loader users run.
TEST(RandomTableTest, PresetFileReadsBackTheSameTable) {
  const std::string dir = ::testing::TempDir() + "/random_table_test";
  std::filesystem::create_directories(dir);
  for (uint64_t seed : {3u, 11u, 42u}) {
    const config::EnvConfig t = RandomTable(seed);
    const std::string path = dir + "/table-" + std::to_string(seed) + ".yaml";
    std::ofstream(path) << RandomTableYaml(t, seed, rl::DescribeGraph(rl::GroundTruthGraph(t)));
    const config::Config loaded = config::LoadConfig(path, {});
    ASSERT_EQ(loaded.env.objects.size(), t.objects.size());
    for (size_t i = 0; i < t.objects.size(); ++i) {
      EXPECT_EQ(loaded.env.objects[i].shape, t.objects[i].shape);
      EXPECT_DOUBLE_EQ(loaded.env.objects[i].size, t.objects[i].size);
      EXPECT_DOUBLE_EQ(loaded.env.objects[i].mass, t.objects[i].mass);
      EXPECT_EQ(loaded.env.objects[i].is_static, t.objects[i].is_static);
    }
    ASSERT_EQ(loaded.env.connections.size(), t.connections.size());
    for (size_t i = 0; i < t.connections.size(); ++i) {
      EXPECT_EQ(loaded.env.connections[i].kind, t.connections[i].kind);
      EXPECT_DOUBLE_EQ(loaded.env.connections[i].length, t.connections[i].length);
      EXPECT_DOUBLE_EQ(loaded.env.connections[i].stiffness, t.connections[i].stiffness);
    }
    EXPECT_EQ(rl::GroundTruthGraph(loaded.env).adjacency, rl::GroundTruthGraph(t).adjacency);
  }
}

// The paper's convention, by hand: action -> arm, arm -> movable objects, both directions of
// a tie between movable objects, nothing into a static object even when it is tied.
TEST(GroundTruthGraphTest, HandMadeTable) {
  config::EnvConfig t;
  t.objects.resize(4);
  t.objects[0].is_static = true;  // entity 1
  t.connections = {{2, 3, config::ConnectionKind::kSpring}, {1, 4, config::ConnectionKind::kRope}};
  EXPECT_EQ(rl::DescribeGraph(rl::GroundTruthGraph(t)), "action->0, 0->2, 0->3, 0->4, 1->4, 2->3, 3->2");
}

// rearrange-4-heldout holds objects 2-4 only: object 1 is in no episode, so no edge touches it
// (the acceptance counted a learned graph without arm->1 as wrong on all three seeds).
TEST(GroundTruthGraphTest, ObjectsOutsideEverySetHaveNoEdges) {
  config::EnvConfig t;
  t.objects.resize(4);
  t.connections = {{1, 2, config::ConnectionKind::kRope}};
  t.object_sets = {{2, 3, 4}};
  t.eval_object_sets = {{2, 3, 4}};
  EXPECT_EQ(rl::DescribeGraph(rl::GroundTruthGraph(t)), "action->0, 0->2, 0->3, 0->4");
  t.eval_object_sets = {{1, 2, 3}};  // in an evaluation set: part of the graph again
  EXPECT_EQ(rl::DescribeGraph(rl::GroundTruthGraph(t)), "action->0, 0->1, 0->2, 0->3, 0->4, 1->2, 2->1");
}

}  // namespace
}  // namespace srics::env
