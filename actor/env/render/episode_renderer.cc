#include "actor/env/render/episode_renderer.h"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "actor/env/mjcf.h"
#include "actor/env/mujoco_util.h"

namespace srics::env {
namespace {

constexpr int kExtraGeoms = 64;                           // room in the scene for the floor and goal markers
constexpr double kMarkerHalfHeight = 0.001;               // flat markers lying on the table
constexpr float kHandGoalRgb[3] = {0.95f, 0.55f, 0.05f};  // orange: unlike the grey hand
// a floor under the table, so that nothing of the frame is the black of an empty scene
constexpr float kFloorRgba[4] = {0.30f, 0.37f, 0.48f, 1.0f};
constexpr double kFloorHalfSize = 4.0, kFloorDepth = 0.02;
// Connections: a capsule between the two objects' centres (where the tendon's sites are), wider
// than MuJoCo's own tendon drawing (5 mm, grey, hardly visible on the white table). A rope is
// brown (the colour of episode_drawing's connections), darker when taut (at 98% of its length or
// more); a spring is violet, darker when stretched beyond its rest length.
constexpr double kConnectionRadius = 0.006;
// (under the scene's lights a colour renders about 1.6 times as bright: these are dark)
constexpr float kRopeRgba[4] = {0.42f, 0.24f, 0.09f, 1.0f};
constexpr float kTautRopeRgba[4] = {0.28f, 0.13f, 0.03f, 1.0f};
constexpr float kSpringRgba[4] = {0.40f, 0.20f, 0.62f, 1.0f};
constexpr float kStretchedSpringRgba[4] = {0.26f, 0.08f, 0.44f, 1.0f};
constexpr double kTautFraction = 0.98;
// A static object carries a pin: a flat washer on its top face (0.4 of its size), a shaft and a
// round head, near black (as episode_drawing's dot on a static object) with a violet tint, so
// that no pixel of it is the dark grey of the hand (tests find the hand by its grey).
constexpr float kPinRgba[4] = {0.14f, 0.03f, 0.20f, 1.0f};
constexpr float kPinHeadRgba[4] = {0.20f, 0.05f, 0.28f, 1.0f};
constexpr double kPinWasherFraction = 0.4, kPinWasherHalfHeight = 0.001;
constexpr double kPinShaftRadius = 0.003, kPinShaftHeight = 0.022, kPinHeadRadius = 0.010;

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
  // room for the model's geoms, a link per tendon, three pin parts per object and the rest
  const int objects = static_cast<int>(config::EffectiveObjects(env_.config()).size());
  mjv_makeScene(m, &mj_->scene, m->ngeom + m->ntendon + 3 * objects + kExtraGeoms);
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
  // no contact points or frames; MuJoCo's own tendon drawing off: AddConnections draws the
  // ropes and springs
  mj_->option.flags[mjVIS_TENDON] = 0;
  // the sites at the objects' centres, where the tendons are attached
  for (int i = 0; i < objects; ++i) {
    const std::string site = "site" + std::to_string(i + 1);
    centre_sites_.push_back(mj_name2id(m, mjOBJ_SITE, site.c_str()));
  }
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

mjvGeom_* EpisodeRenderer::NewGeom() {
  mjvScene& s = mj_->scene;
  if (s.ngeom >= s.maxgeom) return nullptr;
  return s.geoms + s.ngeom++;
}

void EpisodeRenderer::AddConnections() {
  const mjData* d = env_.data();
  const auto& present = env_.present();
  auto is_present = [&](int catalogue) {
    return std::find(present.begin(), present.end(), catalogue) != present.end();
  };
  for (const auto& k : env_.config().connections) {
    // an absent object is parked off the table, its link with it
    if (!is_present(k.first) || !is_present(k.second)) continue;
    const int a = centre_sites_.at(k.first - 1), b = centre_sites_.at(k.second - 1);
    if (a < 0 || b < 0) continue;
    const mjtNum* pa = d->site_xpos + 3 * a;
    const mjtNum* pb = d->site_xpos + 3 * b;
    const double length = std::sqrt((pa[0] - pb[0]) * (pa[0] - pb[0]) + (pa[1] - pb[1]) * (pa[1] - pb[1]) +
                                    (pa[2] - pb[2]) * (pa[2] - pb[2]));
    if (length < 1e-6) continue;  // a connector needs a direction
    const bool rope = k.kind == config::ConnectionKind::kRope;
    const float* rgba = rope ? (length >= kTautFraction * k.length ? kTautRopeRgba : kRopeRgba)
                             : (length > k.length ? kStretchedSpringRgba : kSpringRgba);
    mjvGeom* g = NewGeom();
    if (g == nullptr) return;
    mjv_initGeom(g, mjGEOM_CAPSULE, nullptr, nullptr, nullptr, rgba);
    mjv_makeConnector(g, mjGEOM_CAPSULE, kConnectionRadius, pa[0], pa[1], pa[2], pb[0], pb[1], pb[2]);
    g->category = mjCAT_DECOR;
  }
}

void EpisodeRenderer::AddStaticPins() {
  const auto objects = config::EffectiveObjects(env_.config());
  const auto positions = env_.Positions();
  const auto& present = env_.present();
  const mjtNum identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (size_t k = 0; k < present.size(); ++k) {
    const config::ObjectConfig& o = objects.at(present[k] - 1);
    if (!o.is_static) continue;
    const Vec2& p = positions.at(k + 1);
    const double top = 2 * o.half_height;
    const mjtNum washer_size[3] = {kPinWasherFraction * o.size, kPinWasherFraction * o.size, kPinWasherHalfHeight};
    const mjtNum washer_pos[3] = {p[0], p[1], top + kPinWasherHalfHeight};
    const mjtNum shaft_size[3] = {kPinShaftRadius, kPinShaftRadius, 0.5 * kPinShaftHeight};
    const mjtNum shaft_pos[3] = {p[0], p[1], top + 0.5 * kPinShaftHeight};
    const mjtNum head_size[3] = {kPinHeadRadius, kPinHeadRadius, kPinHeadRadius};
    const mjtNum head_pos[3] = {p[0], p[1], top + kPinShaftHeight};
    const struct {
      int type;
      const mjtNum* size;
      const mjtNum* pos;
      const float* rgba;
    } parts[] = {
        {o.shape == config::ObjectShape::kBox ? mjGEOM_BOX : mjGEOM_CYLINDER, washer_size, washer_pos, kPinRgba},
        {mjGEOM_CYLINDER, shaft_size, shaft_pos, kPinRgba},
        {mjGEOM_SPHERE, head_size, head_pos, kPinHeadRgba}};
    for (const auto& part : parts) {
      mjvGeom* g = NewGeom();
      if (g == nullptr) return;
      mjv_initGeom(g, part.type, part.size, part.pos, identity, part.rgba);
      g->category = mjCAT_DECOR;
      g->specular = 0.2f;
    }
  }
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
  AddConnections();
  AddStaticPins();
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
