// Metrics follow docs/method.md section 1 exactly.

#include <gtest/gtest.h>

#include "actor/env/metrics.h"

namespace srics::env {
namespace {

TEST(MetricsTest, DistancesAveragesAndSuccess) {
  const std::vector<Vec2> pos{{0, 0.4}, {0.1, 0.5}, {0.0, 0.6}, {0.2, 0.7}};
  const std::vector<Vec2> goal{{0, 0.43}, {0.1, 0.54}, {0.0, 0.6}, {0.2, 0.6}};
  const Metrics m = ComputeMetrics(pos, goal, 0.05);
  ASSERT_EQ(m.distances.size(), 4u);
  EXPECT_NEAR(m.distances[0], 0.03, 1e-12);
  EXPECT_NEAR(m.distances[1], 0.04, 1e-12);
  EXPECT_NEAR(m.distances[2], 0.0, 1e-12);
  EXPECT_NEAR(m.distances[3], 0.1, 1e-12);
  EXPECT_NEAR(m.hand_distance, 0.03, 1e-12);
  EXPECT_NEAR(m.avg_distance, 0.17 / 4, 1e-12);           // arm included
  EXPECT_NEAR(m.avg_object_distance, 0.14 / 3, 1e-12);    // objects only
  EXPECT_TRUE(m.success);                                 // 0.17 < 4 * 0.05
  EXPECT_FALSE(ComputeMetrics(pos, goal, 0.04).success);  // 0.17 >= 0.16
}

TEST(MetricsTest, ArmAloneAndBadSizes) {
  const Metrics m = ComputeMetrics(std::vector<Vec2>{{0, 0}}, std::vector<Vec2>{{0.03, 0.04}}, 0.05);
  EXPECT_NEAR(m.avg_distance, 0.05, 1e-12);
  EXPECT_EQ(m.avg_object_distance, 0.0);
  EXPECT_FALSE(m.success);  // strict inequality
  EXPECT_THROW(ComputeMetrics(std::vector<Vec2>{{0, 0}}, std::vector<Vec2>{}, 0.05), std::invalid_argument);
}

}  // namespace
}  // namespace srics::env
