#include "actor/env/render/episode_renderer.h"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "actor/env/mjcf.h"
#include "actor/env/mujoco_util.h"

namespace srics::env {
namespace {

constexpr int kExtraGeoms = 64;              // room in the scene for the goal markers
constexpr double kMarkerHalfHeight = 0.001;  // flat markers lying on the table
constexpr float kHandGoalRgb[3] = {0.95f, 0.55f, 0.05f};  // orange: unlike the grey hand
// a floor under the table, so that nothing of the frame is the black of an empty scene
constexpr float kFloorRgba[4] = {0.30f, 0.37f, 0.48f, 1.0f};
constexpr double kFloorHalfSize = 4.0, kFloorDepth = 0.02;

}  // namespace

void CheckRenderOptions(const RenderOptions& o) {
  auto size = [](const char* name, int v) {
    if (v < 16 || v > 4096 || v % 2 != 0)
      throw std::invalid_argument(std::string(name) + ": expected an even number of pixels in [16, 4096], got " +
                                  std::to_string(v));
  };
  size("width", o.width);
  size("height", o.height);
  if (o.multisamples < 0 || o.multisamples > 16) throw std::invalid_argument("multisamples: expected 0 to 16");
  if (!(o.distance > 0)) throw std::invalid_argument("camera distance: expected > 0");
  for (const double a : {o.goal_alpha, o.active_goal_alpha})
    if (!(a >= 0 && a <= 1)) throw std::invalid_argument("goal alpha: expected a value in [0, 1]");
}

struct EpisodeRenderer::Mujoco {
  mjvScene scene;
  mjvCamera camera;
  mjvOption option;
  mjrContext context;

  Mujoco() {
    mjv_defaultScene(&scene);
    mjv_defaultCamera(&camera);
    mjv_defaultOption(&option);
    mjr_defaultContext(&context);
  }
  ~Mujoco() {
    mjr_freeContext(&context);
    mjv_freeScene(&scene);
  }
  Mujoco(const Mujoco&) = delete;
  Mujoco& operator=(const Mujoco&) = delete;
};

EpisodeRenderer::EpisodeRenderer(RearrangeEnv& env, const GlContext& /*gl: current*/, const RenderOptions& options)
    : env_(env), options_(options), mj_(std::make_unique<Mujoco>()) {
  CheckRenderOptions(options_);
  InstallMujocoHandlers();
  const mjModel* m = env_.model();
  mjv_makeScene(m, &mj_->scene, m->ngeom + m->ntendon + kExtraGeoms);
  // the rendering context from a copy of the model with the multisampling and the offscreen
  // buffer size asked for (the environment's own model is left as it is)
  ModelPtr visual(mj_copyModel(nullptr, m));
  visual->vis.quality.offsamples = options_.multisamples;
  visual->vis.global.offwidth = std::max(visual->vis.global.offwidth, options_.width);
  visual->vis.global.offheight = std::max(visual->vis.global.offheight, options_.height);
  mjr_makeContext(visual.get(), &mj_->context, mjFONTSCALE_100);
  mjr_setBuffer(mjFB_OFFSCREEN, &mj_->context);
  if (mj_->context.currentBuffer != mjFB_OFFSCREEN)
    throw RenderError("MuJoCo has no offscreen framebuffer in this OpenGL context");
  // the OpenGL implementation may cap the buffer's size
  if (options_.width > mj_->context.offWidth || options_.height > mj_->context.offHeight)
    throw RenderError("frames of " + std::to_string(options_.width) + "x" + std::to_string(options_.height) +
                      " exceed MuJoCo's offscreen buffer of " + std::to_string(mj_->context.offWidth) + "x" +
                      std::to_string(mj_->context.offHeight));
  mjvCamera& c = mj_->camera;
  c.type = mjCAMERA_FREE;
  c.lookat[0] = options_.lookat[0];
  c.lookat[1] = options_.lookat[1];
  c.lookat[2] = 0;
  c.distance = options_.distance;
  c.elevation = options_.elevation;
  c.azimuth = options_.azimuth;
  // tendons (ropes, springs) visible; no contact points or frames
  mj_->option.flags[mjVIS_TENDON] = 1;
  image_.width = options_.width;
  image_.height = options_.height;
  image_.rgb.resize(static_cast<size_t>(options_.width) * options_.height * 3);
  bottom_up_.resize(image_.rgb.size());
}

EpisodeRenderer::~EpisodeRenderer() = default;

void EpisodeRenderer::AddFloor() {
  mjvScene& s = mj_->scene;
  if (s.ngeom >= s.maxgeom) return;
  const mjtNum identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const mjtNum size[3] = {kFloorHalfSize, kFloorHalfSize, 0.5 * kFloorDepth};
  const mjtNum pos[3] = {options_.lookat[0], options_.lookat[1], -kFloorDepth};
  mjvGeom* g = s.geoms + s.ngeom;
  mjv_initGeom(g, mjGEOM_BOX, size, pos, identity, kFloorRgba);
  g->category = mjCAT_DECOR;
  ++s.ngeom;
}

void EpisodeRenderer::AddGoalMarkers(int active_entity) {
  mjvScene& s = mj_->scene;
  const auto& goals = env_.goals();
  const auto objects = config::EffectiveObjects(env_.config());
  const auto& present = env_.present();
  const mjtNum identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (size_t e = 0; e < goals.size() && s.ngeom < s.maxgeom; ++e) {
    const double alpha = static_cast<int>(e) == active_entity ? options_.active_goal_alpha : options_.goal_alpha;
    float rgba[4];
    mjtNum size[3] = {0, 0, kMarkerHalfHeight};
    int type = mjGEOM_BOX;
    if (e == 0) {
      const auto& h = env_.config().hand.half_size;
      size[0] = h[0], size[1] = h[1];
      std::copy(kHandGoalRgb, kHandGoalRgb + 3, rgba);
    } else {
      const int catalogue = present[e - 1];
      const config::ObjectConfig& o = objects.at(catalogue - 1);
      const auto rgb = ObjectColor(env_.config(), catalogue);
      for (int k = 0; k < 3; ++k) rgba[k] = static_cast<float>(rgb[k]);
      size[0] = size[1] = o.size;
      if (o.shape != config::ObjectShape::kBox) type = mjGEOM_CYLINDER, size[1] = kMarkerHalfHeight;
    }
    rgba[3] = static_cast<float>(alpha);
    const mjtNum pos[3] = {goals[e][0], goals[e][1], 2 * kMarkerHalfHeight};
    mjvGeom* g = s.geoms + s.ngeom;
    mjv_initGeom(g, type, size, pos, identity, rgba);
    g->category = mjCAT_DECOR;
    g->emission = 0.3f;  // readable under the headlight
    ++s.ngeom;
  }
}

const Image& EpisodeRenderer::Render(int active_entity, const std::string& caption) {
  mjModel* m = const_cast<mjModel*>(env_.model());
  mjData* d = env_.data();
  mjv_updateScene(m, d, &mj_->option, nullptr, &mj_->camera, mjCAT_ALL, &mj_->scene);
  // the lights shine from straight above: their shadows hide under the objects, and a shadow
  // map costs llvmpipe most of a frame
  for (int i = 0; i < mj_->scene.nlight; ++i) mj_->scene.lights[i].castshadow = 0;
  AddFloor();
  if (options_.draw_goals) AddGoalMarkers(active_entity);
  const mjrRect viewport = {0, 0, options_.width, options_.height};
  mjr_render(viewport, &mj_->scene, &mj_->context);
  if (options_.caption && !caption.empty())
    mjr_overlay(mjFONT_NORMAL, mjGRID_TOPLEFT, viewport, caption.c_str(), nullptr, &mj_->context);
  mjr_readPixels(bottom_up_.data(), nullptr, viewport, &mj_->context);
  // OpenGL reads rows from the bottom up
  const size_t row = static_cast<size_t>(options_.width) * 3;
  for (int y = 0; y < options_.height; ++y)
    std::memcpy(image_.rgb.data() + y * row, bottom_up_.data() + (options_.height - 1 - y) * row, row);
  return image_;
}

}  // namespace srics::env
