#pragma once
// The rearrange environment family (docs/method.md section 1). Defaults: Rearrange 3.
// Owned by actor/env; parsed in env_config.cc. Every number of the environment lives here as
// a default member initializer: the env code has no numbers of its own.
//
// Entity numbering: entity 0 is the arm (hand); objects (pucks) are entities 1..n in the
// order of `objects`. Connections, object sets and static flags use these entity numbers.

#include <array>
#include <string>
#include <vector>

namespace srics::config {

// Shape of an object's collision geometry.
enum class ObjectShape { kCylinder, kBox };

// One object of the table (a puck in the paper's environments).
struct ObjectConfig {
  ObjectShape shape = ObjectShape::kCylinder;
  double size = 0.04;          // cylinder radius, or half side of a box (square footprint)
  double half_height = 0.015;  // half of the object's height
  double mass = 0.1;           // kg
  double inertia = 100000.0;   // diagonal rotational inertia: pucks neither tip nor spin
  // a static object's xy is put back to its initial xy after every env step
  bool is_static = false;
  // fixed initial xy instead of a sampled one (empty = sampled)
  std::vector<double> fixed_position;
  // display colour (0..1); empty = palette colour of its entity number
  std::vector<double> rgb;
};

// How two connected objects are linked.
enum class ConnectionKind {
  kRope,    // spatial tendon limited to [0, length]: no force below length (the reference)
  kSpring,  // spatial tendon spring with rest length `length` (the paper's wording)
};

// A link between two objects (entity numbers 1..n).
struct ConnectionConfig {
  int first = 2;
  int second = 3;
  ConnectionKind kind = ConnectionKind::kRope;
  double length = 0.13;  // rope length or spring rest length; goal rule uses it too
  // time constant of the rope's soft length limit (MuJoCo solreflimit, damping ratio 1);
  // MuJoCo's default 0.02 lets a hard pull stretch the rope by ~1 cm, 0.005 by a few mm
  double limit_timeconst = 0.005;
  double stiffness = 20.0;  // N/m, spring only
  double damping = 1.0;     // N s/m, spring only
};

// How a static object stays where it is.
enum class StaticObjects {
  // the reference's: a free body whose xy is put back after every env step. In between it is
  // free: hit by the hand it flies (up to ~20 cm in one step), hits other objects and is put
  // back, so they start moving with no visible cause (docs/results/graph-service-history.md, "Static objects and fast
  // hands")
  kPutBack,
  // a body fixed in the world (a mocap body placed at reset): nothing moves it. The default:
  // the graph service's onsets at a distance need a static object that stays where it is seen
  kFixed,
};

// MuJoCo options and geom defaults.
struct PhysicsConfig {
  double timestep = 0.002;  // s
  int solver_iterations = 50;
  int frame_skip = 50;  // physics steps per env step (one env step = 0.1 s)
  std::vector<double> geom_solref = {0.008, 1.0};
  std::vector<double> geom_solimp = {0.95, 0.95, 0.01};
  double geom_margin = 0.001;
  StaticObjects static_objects = StaticObjects::kFixed;  // put_back: the reference's
  // contacts of a fixed static object (static_objects: fixed): stiff enough that the hand
  // stops at it at full speed (the default contacts let it through at an action of 1, 3.7 cm
  // deep at 0.6); 0.004 s is twice the timestep, MuJoCo's stability limit
  std::vector<double> fixed_object_solref = {0.004, 1.0};
  std::vector<double> fixed_object_solimp = {0.99, 0.999, 0.001};
};

// Table plane and the invisible walls that collide.
struct TableConfig {
  std::vector<double> center = {0.0, 0.6};
  std::vector<double> friction = {1.0, 0.005, 0.001};
  double wall_x = 0.25;       // walls at x = +-wall_x
  double wall_y_low = 0.35;   // wall at y = wall_y_low
  double wall_y_high = 0.76;  // wall at y = wall_y_high
  double wall_half_thickness = 0.005;
  double wall_half_height = 0.1;
  // every object's xy is clipped into this box after every env step
  std::vector<double> object_low = {-0.24, 0.37};
  std::vector<double> object_high = {0.24, 0.75};
};

// The hand: a body welded to a mocap body, moved by the action.
struct HandConfig {
  double action_scale = 0.1;               // m per env step for an action of 1
  double z = 0.02;                         // mocap height, held every step
  std::vector<double> start = {0.0, 0.4};  // also the hand's evaluation goal
  std::vector<double> mocap_low = {-0.245, 0.40};
  std::vector<double> mocap_high = {0.245, 0.75};
  double weld_timeconst = 0.01;  // weld solref (time constant, damping ratio 1)
  // kg of the welded hand body. The weld's force scales with this mass: at 1 kg the hand
  // squeezes a puck 3.5 cm into a wall; at 0.1 kg contacts win (< 5 mm) and pushing works
  double mass = 0.1;
  // collision footprint: a box (half sizes x, y, z) centred on the hand point
  std::vector<double> half_size = {0.02, 0.02, 0.015};
};

// Initial positions, evaluation goals and subgoal goals.
struct SamplingConfig {
  std::vector<double> init_low = {-0.2, 0.45};
  std::vector<double> init_high = {0.2, 0.7};
  double init_min_object_distance = 0.10;  // between objects
  double init_min_hand_distance = 0.06;    // object to hand start
  std::vector<double> goal_low = {-0.2, 0.45};
  std::vector<double> goal_high = {0.2, 0.7};
  double goal_min_object_distance = 0.125;  // between object goals
  double goal_min_hand_distance = 0.075;    // object goal to hand goal
  // goals of subgoals (any entity) for training episodes and relabeling
  std::vector<double> subgoal_low = {-0.2, 0.45};
  std::vector<double> subgoal_high = {0.2, 0.7};
  // spacing rules above are for objects of this bounding radius; larger objects add
  // (radius - reference_radius) to each distance they take part in
  double reference_radius = 0.04;
  // the reference samples a (reachable or not) goal for a static object; false keeps the
  // static object's goal at its initial xy
  bool static_object_random_goal = true;
  // reject goal sets whose tied object's goal (first + length * (sin phi, cos phi)) lies
  // outside goal_low..goal_high (the reference allows unreachable ones)
  bool tied_goal_in_box = true;
  int max_attempts = 100000;  // rejection sampling gives up (with an error) after this
};

struct EnvConfig {
  // number of default pucks when `objects` is not given
  int num_pucks = 3;
  // the object catalogue (entities 1..n); empty = num_pucks default pucks
  std::vector<ObjectConfig> objects;
  std::vector<ConnectionConfig> connections;
  // sets of entity numbers present in a training episode (one drawn per reset); empty =
  // every object present
  std::vector<std::vector<int>> object_sets;
  // the held-out set(s) used by evaluation; empty = same as object_sets
  std::vector<std::vector<int>> eval_object_sets;
  // entity state [one-hot id, x, y] gets vx, vy appended
  bool velocities = false;
  // per-entity success threshold: success = sum of distances < (n + 1) * threshold
  double success_threshold = 0.05;

  PhysicsConfig physics;
  TableConfig table;
  HandConfig hand;
  SamplingConfig sampling;
};

// The object catalogue with the `num_pucks` default applied.
inline std::vector<ObjectConfig> EffectiveObjects(const EnvConfig& config) {
  if (!config.objects.empty()) return config.objects;
  return std::vector<ObjectConfig>(static_cast<size_t>(config.num_pucks));
}

// A rule of the environment's config that is broken: `key` is the key path under `env`
// ("objects[2].mass"), `message` says what is wrong. Empty key = no problem.
struct EnvConfigProblem {
  std::string key;
  std::string message;
  bool ok() const { return key.empty(); }
};

// Checks the cross-field and physical rules (entity numbers in range, connections distinct,
// static objects placeable, fixed objects not overlapping, objects fit on the table, ...).
// Both the YAML parser and the environment call it, so a struct built in code is checked too.
EnvConfigProblem CheckEnvConfig(const EnvConfig& config);

// Radius of the smallest vertical cylinder around the object's footprint.
inline double BoundingRadius(const ObjectConfig& object) {
  return object.shape == ObjectShape::kBox ? object.size * 1.4142135623730951 : object.size;
}

// Human-readable shape name ("cylinder", "box").
inline const char* ShapeName(ObjectShape shape) { return shape == ObjectShape::kBox ? "box" : "cylinder"; }

}  // namespace srics::config
