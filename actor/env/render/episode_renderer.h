#pragma once
// Frames of a rearrange episode from MuJoCo's own renderer: the table (on a blue-grey floor
// that is only in the picture), the hand and the objects as the simulator has them, the episode's goals drawn as
// translucent markers added to the scene (a flat disc or square of the object's size and colour at its goal, a flat
// orange square of the hand's size for the hand's goal; the subgoal being attempted more opaque),
// the constraints (each rope or spring as a capsule between its two objects' centres: a rope
// brown, darker when taut; a spring violet, darker when stretched; a static object with a
// near-black pin on its top), and a caption.
// The markers, links and pins live only in the visual scene (mjvScene): the model and its physics are
// untouched, so a rendered episode is the same episode as an unrendered one.
//
//   GlContext gl;
//   EpisodeRenderer renderer(env, {});
//   const Image& frame = renderer.Render(/*active_entity=*/2, "step 12");

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "actor/env/rearrange_env.h"
#include "actor/env/render/gl_context.h"

struct mjvGeom_;

namespace srics::env {

// How frames look (defaults: 640 x 480, the whole table from the front and above).
struct RenderOptions {
  int width = 640;  // pixels; even (video encoders want even sizes)
  int height = 480;
  Vec2 lookat{0.0, 0.56};           // camera target on the table, metres
  double distance = 0.72;           // camera distance to the target, metres
  double elevation = -58;           // degrees (negative: looking down)
  double azimuth = 90;              // degrees (90: looking along +y, the table's depth)
  double goal_alpha = 0.35;         // opacity of the goal markers
  double active_goal_alpha = 0.75;  // opacity of the marker of the subgoal being attempted
  int multisamples = 0;             // anti-aliasing samples per pixel (4: smoother edges, 2x the time on llvmpipe)
  bool draw_goals = true;
  bool caption = true;  // the caption's text in the top-left corner
};

// Throws std::invalid_argument naming the field when a value is out of range (sizes from 16
// to 4096 and even, distance > 0, alphas in [0, 1], multisamples in [0, 16]).
void CheckRenderOptions(const RenderOptions& options);

// An RGB picture, rows from top to bottom, 3 bytes per pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;
};

class EpisodeRenderer {
 public:
  // Makes MuJoCo's rendering context for env's model (an offscreen buffer of the frame size)
  // in the current GL context (`gl` must be current on this thread and outlive the renderer).
  // Throws std::invalid_argument for bad options, RenderError when MuJoCo cannot render (e.g.
  // the OpenGL implementation has no offscreen buffer that big).
  EpisodeRenderer(RearrangeEnv& env, const GlContext& gl, const RenderOptions& options);
  ~EpisodeRenderer();
  EpisodeRenderer(const EpisodeRenderer&) = delete;
  EpisodeRenderer& operator=(const EpisodeRenderer&) = delete;

  // The environment's current state with its goals (env.goals()); `active_entity` is the
  // entity whose subgoal is being attempted (-1: none, or the full goal). The image is valid
  // until the next call.
  const Image& Render(int active_entity, const std::string& caption);

  const RenderOptions& options() const { return options_; }

 private:
  struct Mujoco;
  mjvGeom_* NewGeom();  // the scene's next free geom, or null when it is full
  void AddFloor();
  void AddConnections();
  void AddStaticPins();
  void AddGoalMarkers(int active_entity);

  RearrangeEnv& env_;
  RenderOptions options_;
  std::unique_ptr<Mujoco> mj_;
  std::vector<int> centre_sites_;  // per catalogue object 1..n, its centre site's id (-1: none)
  std::vector<uint8_t> bottom_up_;
  Image image_;
};

}  // namespace srics::env
