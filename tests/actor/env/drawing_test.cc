// The top-down drawing writes a PNG of the table's size and an SVG with every entity.

#include <gtest/gtest.h>

#include <filesystem>

#include "actor/env/episode_drawing.h"
#include "actor/env/rearrange_env.h"
#include "common/config/config.h"
#include "tests/common/files/test_files.h"

namespace srics::env {
namespace {

EpisodeTrace RelationalTrace() {
  const config::EnvConfig c =
      config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/env/relational-4.yaml").env;
  RearrangeEnv env(c);
  env.Reset(2);
  EpisodeTrace trace;
  trace.config = c;
  trace.present = env.present();
  trace.goals = env.goals();
  trace.positions.push_back(env.Positions());
  for (int t = 0; t < 10; ++t) {
    env.Step(std::vector<double>{0.5, 0.8});
    trace.positions.push_back(env.Positions());
  }
  trace.title = "test";
  return trace;
}

using files::testing::ReadFile;

TEST(DrawingTest, WritesPngAndSvg) {
  const auto dir = std::filesystem::temp_directory_path() / "srics_drawing_test";
  std::filesystem::create_directories(dir);
  const EpisodeTrace trace = RelationalTrace();
  DrawEpisode(trace, (dir / "e.png").string());
  const std::string png = ReadFile(dir / "e.png");
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  // IHDR width and height (big endian) match 1200 px/m over the walls plus a 2 cm border
  const auto be32 = [&](size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) | (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  EXPECT_EQ(be32(16), 660);       // (0.255 + 0.02) * 2 * 1200
  EXPECT_NEAR(be32(20), 552, 1);  // (0.765 - 0.345 + 0.04) * 1200
  DrawEpisode(trace, (dir / "e.svg").string());
  const std::string svg = ReadFile(dir / "e.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_EQ(std::count(svg.begin(), svg.end(), '\n') > 10, true);
  EXPECT_NE(svg.find("<polyline"), std::string::npos);
  EXPECT_THROW(DrawEpisode(trace, (dir / "e.bmp").string()), std::runtime_error);
  EpisodeTrace broken = trace;
  broken.goals.pop_back();
  EXPECT_THROW(DrawEpisode(broken, (dir / "x.png").string()), std::runtime_error);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace srics::env
