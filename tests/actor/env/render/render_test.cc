// The offscreen renderer draws the simulator's state (hand and objects where the physics has
// them, goals as markers that leave the physics alone) and the video writer's files hold
// exactly the frames given.

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "actor/env/render/episode_renderer.h"
#include "actor/env/render/gl_context.h"
#include "actor/env/render/video_writer.h"
#include "tests/actor/env/env_presets.h"
#include "tests/actor/env/render/frames_testing.h"
#include "tests/common/files/test_files.h"

#include "tests/sanitizer.h"
#ifdef SRICS_TESTING_ASAN
#include <dlfcn.h>

#include <cstdlib>
#include <sstream>
#include <string>

namespace {
// Under AddressSanitizer (./tests/sanitize.sh): Mesa unloads its software driver at eglTerminate
// while the driver's own globals still hold a few blocks (240 bytes), which LeakSanitizer then
// reports as leaks of an unknown module at exit, with nothing a suppression could name. Keeping
// the driver loaded (RTLD_NODELETE) leaves those blocks reachable, as they are: Mesa's, not ours.
const bool g_mesa_driver_kept = [] {
  const char* env = std::getenv("LIBGL_DRIVERS_PATH");
  std::stringstream dirs(env != nullptr ? env : "/usr/lib/x86_64-linux-gnu/dri:/usr/lib/dri");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (dlopen((dir + "/swrast_dri.so").c_str(), RTLD_LAZY | RTLD_NODELETE) != nullptr) return true;
  return false;
}();
}  // namespace
#endif

namespace srics::env {
namespace {

namespace fs = std::filesystem;
using testing::DecodeVideo;
using testing::DifferingPixels;
using testing::FindHand;
using testing::Pixel;
using testing::PixelAt;
using testing::PixelOf;
using testing::PixelStdDev;
using testing::ReadPng;

class RenderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { gl_ = new GlContext(); }
  static void TearDownTestSuite() {
    delete gl_;
    gl_ = nullptr;
  }

  static GlContext* gl_;
  files::testing::ScratchFolder dir_{"srics_render_test"};
};
GlContext* RenderTest::gl_ = nullptr;

TEST_F(RenderTest, ContextSaysWhatRendersIt) { EXPECT_NE(gl_->description().find("EGL"), std::string::npos); }

TEST_F(RenderTest, FrameShowsTheTableHandAndGoalsWithoutChangingThePhysics) {
  RearrangeEnv env(testing::Preset("relational-4"));
  env.Reset(3);
  const std::vector<double> qpos_before(env.data()->qpos, env.data()->qpos + env.model()->nq);
  RenderOptions options;
  options.caption = false;
  EpisodeRenderer renderer(env, *gl_, options);
  const Image with_goals = renderer.Render(-1, "");
  ASSERT_EQ(with_goals.width, 640);
  ASSERT_EQ(with_goals.rgb.size(), 640u * 480 * 3);
  EXPECT_GT(PixelStdDev(with_goals), 20) << "a blank frame";
  EXPECT_TRUE(FindHand(with_goals).has_value()) << "no hand in the frame";

  // the goal markers are only in the picture: the simulation state is the same
  options.draw_goals = false;
  EpisodeRenderer plain(env, *gl_, options);
  const Image without_goals = plain.Render(-1, "");
  EXPECT_GT(DifferingPixels(with_goals, without_goals), 500) << "goal markers not drawn";
  EXPECT_EQ(qpos_before, std::vector<double>(env.data()->qpos, env.data()->qpos + env.model()->nq));
  WritePng((dir_ / "frame.png").string(), with_goals.rgb.data(), with_goals.width, with_goals.height);
  EXPECT_TRUE(ReadPng((dir_ / "frame.png").string()).has_value());
}

TEST_F(RenderTest, HandMovingRightMovesItsPixelsRight) {
  RearrangeEnv env(testing::Preset("rearrange-1"));
  env.Reset(1);
  RenderOptions options;
  options.caption = false;
  EpisodeRenderer renderer(env, *gl_, options);
  const auto before = FindHand(renderer.Render(-1, ""));
  const double x0 = env.Positions()[0][0];
  for (int t = 0; t < 2; ++t) env.Step(std::vector<double>{1.0, 0.0});
  const double moved = env.Positions()[0][0] - x0;
  ASSERT_GT(moved, 0.1);
  const auto after = FindHand(renderer.Render(-1, ""));
  ASSERT_TRUE(before && after);
  // +x is to the right in the picture (the camera looks along +y), about 600 px per metre
  EXPECT_GT(after->x - before->x, 100 * moved);
  EXPECT_LT(std::abs(after->y - before->y), 20);
}

// The pixels of the segment between two tied objects' centres (at the centres' height) that
// nothing else hides: farther than `clear` from each object's centre and from every other entity
// (the objects' bodies, their tops projected a little further up the picture, and the hand).
std::vector<const uint8_t*> LinkPixels(const Image& frame, const RearrangeEnv& env, const RenderOptions& options, int a,
                                       int b, double clear) {
  const auto positions = env.Positions();
  const double fovy = env.model()->vis.global.fovy;
  const double z = config::EffectiveObjects(env.config()).at(env.present()[a - 1] - 1).half_height;
  const Vec2 pa = positions[a], pb = positions[b];
  const Pixel from = PixelOf(options, fovy, pa[0], pa[1], z), to = PixelOf(options, fovy, pb[0], pb[1], z);
  const int samples = static_cast<int>(std::hypot(to.x - from.x, to.y - from.y));  // about one a pixel
  std::vector<const uint8_t*> pixels;
  for (int i = 0; i <= samples; ++i) {
    const double t = static_cast<double>(i) / std::max(samples, 1);
    const double x = pa[0] + t * (pb[0] - pa[0]), y = pa[1] + t * (pb[1] - pa[1]);
    bool hidden = false;
    for (size_t e = 0; e < positions.size(); ++e)
      if (std::hypot(x - positions[e][0], y - positions[e][1]) < clear) hidden = true;
    if (hidden) continue;
    const Pixel p = PixelOf(options, fovy, x, y, z);
    pixels.push_back(PixelAt(frame, p.x, p.y));
  }
  return pixels;
}

// Relational Rearrange 4 (puck 1 static, pucks 2 and 3 tied by a rope): the rope is drawn between
// the tied pucks (brown, along the whole visible segment between their centres), the static puck
// carries a near-black pin at its centre; with the link made a spring, it is drawn violet. Before
// the constraints were drawn, the segment showed MuJoCo's 5 mm grey tendon (or the white table)
// and the static puck's centre its own green.
TEST_F(RenderTest, TheRopeRunsBetweenTheTiedPucksAndAPinMarksTheStaticOne) {
  RenderOptions options;
  options.caption = false;
  auto colour = [](const uint8_t* p) {
    return "(" + std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " + std::to_string(p[2]) + ")";
  };
  for (const auto kind : {config::ConnectionKind::kRope, config::ConnectionKind::kSpring}) {
    SCOPED_TRACE(kind == config::ConnectionKind::kRope ? "rope" : "spring");
    config::EnvConfig c = testing::Preset("relational-4");
    ASSERT_EQ(c.connections.size(), 1u);
    c.connections[0].kind = kind;
    RearrangeEnv env(c);
    // a table where the tied pucks are apart and nothing else is near the segment between them
    const double clear = 0.04 + 0.01;  // the pucks' radius, and their tops' reach up the picture
    int a = 0, b = 0;
    bool found = false;
    for (uint64_t seed = 1; seed <= 1000 && !found; ++seed) {
      env.Reset(seed);
      const auto& present = env.present();
      const auto at = [&](int catalogue) {
        return static_cast<int>(std::find(present.begin(), present.end(), catalogue) - present.begin()) + 1;
      };
      a = at(c.connections[0].first), b = at(c.connections[0].second);
      if (a > static_cast<int>(present.size()) || b > static_cast<int>(present.size())) continue;
      const auto p = env.Positions();
      if (std::hypot(p[a][0] - p[b][0], p[a][1] - p[b][1]) < 0.12) continue;  // the rope: 0.13
      // the others (the hand too) well away from the segment
      bool crowded = false;
      for (size_t e = 0; e < p.size(); ++e) {
        if (static_cast<int>(e) == a || static_cast<int>(e) == b) continue;
        for (int i = 0; i <= 20; ++i) {
          const double t = i / 20.0;
          if (std::hypot(p[a][0] + t * (p[b][0] - p[a][0]) - p[e][0], p[a][1] + t * (p[b][1] - p[a][1]) - p[e][1]) <
              0.065)
            crowded = true;
        }
      }
      found = !crowded;
    }
    ASSERT_TRUE(found) << "no reset with the tied pucks apart and the segment clear";
    EpisodeRenderer renderer(env, *gl_, options);
    const Image& frame = renderer.Render(-1, "");
    // SRICS_RENDER_TEST_FRAMES=DIR keeps the frames to look at
    if (const char* keep = std::getenv("SRICS_RENDER_TEST_FRAMES"))
      WritePng(std::string(keep) + (kind == config::ConnectionKind::kRope ? "/rope.png" : "/spring.png"),
               frame.rgb.data(), frame.width, frame.height);

    // the projection is the renderer's: the hand's dark pixels centre on the hand's top
    const auto hand = FindHand(frame);
    ASSERT_TRUE(hand.has_value());
    const Vec2 h = env.Positions()[0];
    const Pixel hand_top = PixelOf(options, env.model()->vis.global.fovy, h[0], h[1], 0.03);
    EXPECT_NEAR(hand->x, hand_top.x, 6);
    EXPECT_NEAR(hand->y, hand_top.y, 8);

    const auto link = LinkPixels(frame, env, options, a, b, clear);
    ASSERT_GE(link.size(), 8u) << "too little of the segment in view";
    int drawn = 0;
    std::string seen;
    for (const uint8_t* p : link) {
      const int r = p[0], g = p[1], bl = p[2];
      const bool like = kind == config::ConnectionKind::kRope ? r > g + 25 && g > bl + 15 && r < 235  // brown
                                                              : bl > g + 60 && r > g + 20;            // violet
      drawn += like;
      if (!like && seen.size() < 200) seen += colour(p) + " ";
    }
    EXPECT_GE(drawn, static_cast<int>(0.9 * link.size()))
        << drawn << " of " << link.size() << " pixels of the segment in the link's colour; others: " << seen;

    // the static puck's pin: near black (violet-tinted) at the centre of its top; the other
    // pucks show their bright colour there
    const auto objects = config::EffectiveObjects(c);
    int static_entities = 0;
    for (size_t k = 0; k < env.present().size(); ++k) {
      const auto& o = objects.at(env.present()[k] - 1);
      const Vec2 p = env.Positions()[k + 1];
      const Pixel centre = PixelOf(options, env.model()->vis.global.fovy, p[0], p[1], 2 * o.half_height);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const uint8_t* q = PixelAt(frame, centre.x + dx, centre.y + dy);
          const bool pin = std::max({q[0], q[1], q[2]}) < 110 && q[2] > q[1] + 20;
          EXPECT_EQ(pin, o.is_static) << "object " << env.present()[k] << " centre " << colour(q);
        }
      static_entities += o.is_static;
    }
    EXPECT_EQ(static_entities, 1);
  }
}

TEST_F(RenderTest, RendersAnyEvenSizeAndRejectsOthers) {
  RenderOptions odd;
  odd.width = 641;
  EXPECT_THROW(CheckRenderOptions(odd), std::invalid_argument);
  RenderOptions tiny;
  tiny.height = 8;
  EXPECT_THROW(CheckRenderOptions(tiny), std::invalid_argument);
  // beyond the model's own offscreen buffer (640 x 480): the renderer makes a larger one
  RearrangeEnv env(testing::Preset("rearrange-1"));
  RenderOptions large;
  large.width = 1280;
  large.height = 720;
  large.caption = false;
  EpisodeRenderer renderer(env, *gl_, large);
  const Image& frame = renderer.Render(-1, "");
  EXPECT_EQ(frame.rgb.size(), 1280u * 720 * 3);
  EXPECT_GT(PixelStdDev(frame), 20);
  EXPECT_TRUE(FindHand(frame).has_value());
}

// Frames of one colour each, so a decoded frame tells which one it is.
std::vector<uint8_t> Solid(int width, int height, uint8_t r, uint8_t g, uint8_t b) {
  std::vector<uint8_t> rgb(static_cast<size_t>(width) * height * 3);
  for (size_t p = 0; p < rgb.size(); p += 3) rgb[p] = r, rgb[p + 1] = g, rgb[p + 2] = b;
  return rgb;
}

TEST_F(RenderTest, PngFramesHoldEveryFrame) {
  VideoWriter video((dir_ / "frames").string(), 32, 16, {.format = VideoFormat::kPng});
  for (int i = 0; i < 3; ++i) video.Write(Solid(32, 16, static_cast<uint8_t>(80 * i), 10, 200).data());
  video.Close();
  EXPECT_EQ(video.frames(), 3);
  for (int i = 0; i < 3; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame-%05d.png", i);
    const auto image = ReadPng((dir_ / "frames" / name).string());
    ASSERT_TRUE(image.has_value()) << name;
    EXPECT_EQ(image->rgb, Solid(32, 16, static_cast<uint8_t>(80 * i), 10, 200));
  }
}

TEST_F(RenderTest, Mp4HoldsTheFramesInOrder) {
  if (!FfmpegAvailable()) GTEST_SKIP() << "ffmpeg is not installed (deploy/install-deps.sh video)";
  const std::string path = (dir_ / "clip.mp4").string();
  VideoWriter video(path, 64, 48, {.format = VideoFormat::kMp4, .fps = 10});
  const uint8_t reds[] = {20, 120, 220, 120, 20};
  for (uint8_t r : reds) video.Write(Solid(64, 48, r, 60, 60).data());
  video.Close();
  EXPECT_FALSE(fs::exists(path + ".log"));
  const auto frames = DecodeVideo(path, 64, 48, (dir_ / "clip.rgb").string());
  ASSERT_EQ(frames.size(), 5u);
  for (size_t i = 0; i < frames.size(); ++i) EXPECT_NEAR(frames[i].rgb[3 * (24 * 64 + 32)], reds[i], 12) << i;
}

TEST_F(RenderTest, FfmpegFailuresAreErrorsWithItsMessage) {
  EXPECT_THROW(VideoWriter((dir_ / "x.mp4").string(), 64, 48, {.ffmpeg = "/nonexistent/ffmpeg"}), VideoError);
  if (!FfmpegAvailable()) GTEST_SKIP() << "ffmpeg is not installed";
  // a folder where the file should be: ffmpeg cannot write it
  fs::create_directories(dir_ / "taken.mp4");
  VideoWriter video((dir_ / "taken.mp4").string(), 64, 48, {});
  try {
    for (int i = 0; i < 50; ++i) video.Write(Solid(64, 48, 1, 2, 3).data());
    video.Close();
    FAIL() << "no error";
  } catch (const VideoError& e) {
    EXPECT_NE(std::string(e.what()).find("taken.mp4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace srics::env
