#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <sstream>

#include "common/config/sections.h"

namespace srics::config {
namespace {

std::string Num(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

std::string ObjectKey(size_t i) { return "objects[" + std::to_string(i) + "]"; }

EnvConfigProblem Problem(std::string key, std::string message) {
  return EnvConfigProblem{std::move(key), std::move(message)};
}

// A box given as two 2-vectors must have low < high on both axes.
EnvConfigProblem CheckBox(const std::string& low_key, const std::vector<double>& low, const std::vector<double>& high) {
  if (low.size() != 2 || high.size() != 2) return Problem(low_key, "expected 2 numbers");
  if (!(low[0] < high[0] && low[1] < high[1]))
    return Problem(low_key, "must be below the matching *_high on both axes");
  return {};
}

// Checks one set of entity numbers (1..n, no repeats, connections whole).
EnvConfigProblem CheckObjectSet(const std::string& key, const std::vector<int>& set, int n,
                                const std::vector<ConnectionConfig>& connections) {
  if (set.empty()) return Problem(key, "an object set needs at least one object");
  std::set<int> seen;
  for (int e : set) {
    if (e < 1 || e > n)
      return Problem(key,
                     "entity " + std::to_string(e) + " is not an object (objects are 1.." + std::to_string(n) + ")");
    if (!seen.insert(e).second) return Problem(key, "entity " + std::to_string(e) + " repeated");
  }
  for (const auto& c : connections) {
    if (seen.count(c.first) != seen.count(c.second))
      return Problem(key, "objects " + std::to_string(c.first) + " and " + std::to_string(c.second) +
                              " are connected: a set has both or neither");
  }
  return {};
}

// The inner faces of the walls: they bound every object's footprint.
struct InnerWalls {
  double x, y_low, y_high;
};

InnerWalls InnerWallsOf(const TableConfig& t) {
  return {t.wall_x - t.wall_half_thickness, t.wall_y_low + t.wall_half_thickness,
          t.wall_y_high - t.wall_half_thickness};
}

// Room between the walls, the boxes (low < high) and the hand's vector sizes.
EnvConfigProblem CheckTableAndHand(const EnvConfig& c) {
  const TableConfig& t = c.table;
  const InnerWalls in = InnerWallsOf(t);
  if (!(in.x > 0 && in.y_low < in.y_high)) return Problem("table", "walls leave no room");
  for (const auto& [key, low, high] :
       {std::tuple{"table.object_low", t.object_low, t.object_high},
        std::tuple{"hand.mocap_low", c.hand.mocap_low, c.hand.mocap_high},
        std::tuple{"sampling.init_low", c.sampling.init_low, c.sampling.init_high},
        std::tuple{"sampling.goal_low", c.sampling.goal_low, c.sampling.goal_high},
        std::tuple{"sampling.subgoal_low", c.sampling.subgoal_low, c.sampling.subgoal_high}}) {
    if (auto p = CheckBox(key, low, high); !p.ok()) return p;
  }
  if (c.hand.start.size() != 2) return Problem("hand.start", "expected 2 numbers");
  if (c.hand.half_size.size() != 3) return Problem("hand.half_size", "expected 3 numbers");
  return {};
}

// One object (named `key`): positive physical quantities, a size that fits between the
// walls, a fixed position clear of the walls and the hand.
EnvConfigProblem CheckObject(const EnvConfig& c, const ObjectConfig& o, const std::string& key) {
  if (!(o.mass > 0)) return Problem(key + ".mass", "must be positive, got " + Num(o.mass));
  if (!(o.size > 0)) return Problem(key + ".size", "must be positive, got " + Num(o.size));
  if (!(o.half_height > 0)) return Problem(key + ".half_height", "must be positive, got " + Num(o.half_height));
  if (!(o.inertia > 0)) return Problem(key + ".inertia", "must be positive, got " + Num(o.inertia));
  if (!o.rgb.empty() && o.rgb.size() != 3) return Problem(key + ".rgb", "expected 3 numbers");
  const InnerWalls in = InnerWallsOf(c.table);
  const double r = BoundingRadius(o);
  // the object's centre must have a non-empty box inside the sampling box and the walls
  const double lo_x = std::max(c.sampling.init_low[0], -in.x + r);
  const double hi_x = std::min(c.sampling.init_high[0], in.x - r);
  const double lo_y = std::max(c.sampling.init_low[1], in.y_low + r);
  const double hi_y = std::min(c.sampling.init_high[1], in.y_high - r);
  if (!(lo_x < hi_x && lo_y < hi_y))
    return Problem(key + ".size",
                   "an object of bounding radius " + Num(r) + " does not fit on the table between the walls");
  if (o.fixed_position.empty()) return {};
  if (o.fixed_position.size() != 2) return Problem(key + ".fixed_position", "expected 2 numbers (x, y)");
  const double x = o.fixed_position[0], y = o.fixed_position[1];
  if (std::abs(x) + r > in.x || y - r < in.y_low || y + r > in.y_high)
    return Problem(key + ".fixed_position", "(" + Num(x) + ", " + Num(y) + ") puts the object through a wall");
  const double dh = std::hypot(x - c.hand.start[0], y - c.hand.start[1]);
  if (dh < r + c.hand.half_size[1]) return Problem(key + ".fixed_position", "overlaps the hand's start position");
  return {};
}

// Fixed objects must not overlap each other.
EnvConfigProblem CheckFixedOverlaps(const std::vector<ObjectConfig>& objects) {
  for (size_t i = 0; i < objects.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const auto& a = objects[i];
      const auto& b = objects[j];
      if (a.fixed_position.empty() || b.fixed_position.empty()) continue;
      const double d = std::hypot(a.fixed_position[0] - b.fixed_position[0], a.fixed_position[1] - b.fixed_position[1]);
      if (d < BoundingRadius(a) + BoundingRadius(b))
        return Problem(ObjectKey(i) + ".fixed_position", "overlapping fixed objects: entities " +
                                                             std::to_string(j + 1) + " and " + std::to_string(i + 1) +
                                                             " are " + Num(d) + " apart, need " +
                                                             Num(BoundingRadius(a) + BoundingRadius(b)));
    }
  }
  return {};
}

// Connections: distinct existing objects, each object tied behind at most one other, listed
// in placing order, with a usable length and stiffness.
EnvConfigProblem CheckConnections(const EnvConfig& c, const std::vector<ObjectConfig>& objects) {
  const int n = static_cast<int>(objects.size());
  std::set<int> seconds;
  std::set<std::pair<int, int>> pairs;
  for (size_t i = 0; i < c.connections.size(); ++i) {
    const ConnectionConfig& k = c.connections[i];
    const std::string key = "connections[" + std::to_string(i) + "]";
    if (k.first < 1 || k.first > n || k.second < 1 || k.second > n)
      return Problem(key, "objects are entities 1.." + std::to_string(n) + ", got " + std::to_string(k.first) +
                              " and " + std::to_string(k.second));
    if (k.first == k.second) return Problem(key, "an object cannot be tied to itself");
    if (!pairs.insert({std::min(k.first, k.second), std::max(k.first, k.second)}).second)
      return Problem(key, "the same pair is connected twice");
    if (!seconds.insert(k.second).second)
      return Problem(key, "entity " + std::to_string(k.second) + " is the second object of two connections");
    // the first object's position must be known before the second's: first is never a
    // later connection's second (this also rules out cycles)
    for (size_t j = i + 1; j < c.connections.size(); ++j)
      if (c.connections[j].second == k.first)
        return Problem(key, "list the connection that places entity " + std::to_string(k.first) + " before this one");
    if (!(k.length > 0)) return Problem(key + ".length", "must be positive");
    if (k.length < c.sampling.init_min_object_distance)
      return Problem(key + ".length", "must be at least sampling.init_min_object_distance (" +
                                          Num(c.sampling.init_min_object_distance) + ")");
    // the tie sets the pair's goal distance: at its full length the two must not overlap
    if (const double touching = BoundingRadius(objects[k.first - 1]) + BoundingRadius(objects[k.second - 1]);
        k.length < touching)
      return Problem(key + ".length",
                     "must be at least the two objects' bounding radii together (" + Num(touching) + ")");
    if (!objects[k.second - 1].fixed_position.empty())
      return Problem(
          key, "entity " + std::to_string(k.second) + " is placed by its connection: it cannot have a fixed_position");
    if (k.kind == ConnectionKind::kSpring && !(k.stiffness > 0))
      return Problem(key + ".stiffness", "a spring needs a positive stiffness");
  }
  return {};
}

// Every set of object_sets and eval_object_sets.
EnvConfigProblem CheckObjectSets(const EnvConfig& c, int n) {
  for (const auto& [name, sets] :
       {std::pair{"object_sets", &c.object_sets}, std::pair{"eval_object_sets", &c.eval_object_sets}}) {
    for (size_t i = 0; i < sets->size(); ++i) {
      auto p = CheckObjectSet(std::string(name) + "[" + std::to_string(i) + "]", (*sets)[i], n, c.connections);
      if (!p.ok()) return p;
    }
  }
  return {};
}

// The objects must fit: discs of half the required spacing cannot overlap inside the
// sampling box grown by that spacing (densest packing of discs: pi / sqrt(12)).
EnvConfigProblem CheckObjectsFit(const EnvConfig& c, const std::vector<ObjectConfig>& objects) {
  for (const auto& [name, low, high, spacing] :
       {std::tuple{"sampling.init_min_object_distance", c.sampling.init_low, c.sampling.init_high,
                   c.sampling.init_min_object_distance},
        std::tuple{"sampling.goal_min_object_distance", c.sampling.goal_low, c.sampling.goal_high,
                   c.sampling.goal_min_object_distance}}) {
    double needed = 0;
    double widest = 0;
    for (const auto& o : objects) {
      const double d = spacing + 2 * std::max(0.0, BoundingRadius(o) - c.sampling.reference_radius);
      needed += std::numbers::pi * d * d / 4;
      widest = std::max(widest, d);
    }
    const double room = std::numbers::pi / std::sqrt(12.0) * (high[0] - low[0] + widest) * (high[1] - low[1] + widest);
    if (needed > room)
      return Problem("objects", std::to_string(objects.size()) + " objects do not fit on the table with " + name +
                                    " = " + Num(spacing) + " (more objects than fit the table)");
  }
  return {};
}

// The vector sizes of physics and table.
EnvConfigProblem CheckVectorSizes(const EnvConfig& c) {
  if (c.physics.geom_solref.size() != 2) return Problem("physics.geom_solref", "expected 2 numbers");
  if (c.physics.geom_solimp.size() != 3) return Problem("physics.geom_solimp", "expected 3 numbers");
  if (c.physics.fixed_object_solref.size() != 2) return Problem("physics.fixed_object_solref", "expected 2 numbers");
  if (c.physics.fixed_object_solimp.size() != 3) return Problem("physics.fixed_object_solimp", "expected 3 numbers");
  if (c.table.center.size() != 2) return Problem("table.center", "expected 2 numbers");
  if (c.table.friction.size() != 3) return Problem("table.friction", "expected 3 numbers");
  return {};
}

}  // namespace

EnvConfigProblem CheckEnvConfig(const EnvConfig& c) {
  const std::vector<ObjectConfig> objects = EffectiveObjects(c);
  const int n = static_cast<int>(objects.size());
  if (n < 1 || n > 6) return Problem("objects", "expected 1 to 6 objects, got " + std::to_string(n));
  if (auto p = CheckTableAndHand(c); !p.ok()) return p;
  for (size_t i = 0; i < objects.size(); ++i)
    if (auto p = CheckObject(c, objects[i], ObjectKey(i)); !p.ok()) return p;
  if (auto p = CheckFixedOverlaps(objects); !p.ok()) return p;
  if (auto p = CheckConnections(c, objects); !p.ok()) return p;
  if (auto p = CheckObjectSets(c, n); !p.ok()) return p;
  if (auto p = CheckObjectsFit(c, objects); !p.ok()) return p;
  return CheckVectorSizes(c);
}

namespace {

void ParseObject(YamlSection& s, ObjectConfig* o) {
  s.ReadEnum<ObjectShape>("shape", &o->shape, {{"cylinder", ObjectShape::kCylinder}, {"box", ObjectShape::kBox}});
  s.ReadDouble("size", &o->size, 1e-4, 1.0);
  s.ReadDouble("half_height", &o->half_height, 1e-4, 1.0);
  s.ReadDouble("mass", &o->mass, 1e-6, 1e3);
  s.ReadDouble("inertia", &o->inertia, 1e-9, 1e9);
  s.ReadBool("static", &o->is_static);
  s.ReadDoubleList("fixed_position", &o->fixed_position, 2, -10, 10);
  s.ReadDoubleList("rgb", &o->rgb, 3, 0, 1);
  s.Finish();
}

void ParseConnection(YamlSection& s, ConnectionConfig* k) {
  std::vector<int> objects;
  if (!s.Has("objects")) s.FailRule("objects", "missing: expected [first, second] entity numbers");
  s.ReadIntList("objects", &objects, 1, 6);
  if (objects.size() != 2) s.Fail("objects", "a list of 2 entity numbers in [1, 6]");
  k->first = objects[0];
  k->second = objects[1];
  s.ReadEnum<ConnectionKind>("kind", &k->kind, {{"rope", ConnectionKind::kRope}, {"spring", ConnectionKind::kSpring}});
  s.ReadDouble("length", &k->length, 1e-3, 1.0);
  s.ReadDouble("limit_timeconst", &k->limit_timeconst, 1e-4, 1);
  s.ReadDouble("stiffness", &k->stiffness, 0, 1e6);
  s.ReadDouble("damping", &k->damping, 0, 1e6);
  s.Finish();
}

void ParseObjectSets(YamlSection& s, const std::string& key, std::vector<std::vector<int>>* out) {
  if (!s.Has(key)) return;
  out->clear();
  for (YamlSection item : s.ChildList(key)) {
    std::vector<int> set;
    if (!item.Has("present")) item.FailRule("present", "missing: expected a list of entity numbers");
    item.ReadIntList("present", &set, 1, 6);
    item.Finish();
    out->push_back(std::move(set));
  }
}

// Parses the list under `key` item by item into *out; the items' sections are kept in *items
// so that a rule broken later can name the item's own line.
template <typename T>
void ParseItems(YamlSection& s, const std::string& key, void (*parse)(YamlSection&, T*), std::vector<T>* out,
                std::vector<YamlSection>* items) {
  out->clear();
  *items = s.ChildList(key);
  for (YamlSection& item : *items) {
    T value;
    parse(item, &value);
    out->push_back(std::move(value));
  }
}

void ParsePhysics(YamlSection p, PhysicsConfig* out) {
  p.ReadDouble("timestep", &out->timestep, 1e-5, 0.1);
  p.ReadInt("solver_iterations", &out->solver_iterations, 1, 10000);
  p.ReadInt("frame_skip", &out->frame_skip, 1, 10000);
  p.ReadDoubleList("geom_solref", &out->geom_solref, 2, -1e6, 1e6);
  p.ReadDoubleList("geom_solimp", &out->geom_solimp, 3, 0, 1);
  p.ReadDouble("geom_margin", &out->geom_margin, 0, 0.1);
  p.ReadEnum<StaticObjects>("static_objects", &out->static_objects,
                            {{"put_back", StaticObjects::kPutBack}, {"fixed", StaticObjects::kFixed}});
  p.ReadDoubleList("fixed_object_solref", &out->fixed_object_solref, 2, -1e6, 1e6);
  p.ReadDoubleList("fixed_object_solimp", &out->fixed_object_solimp, 3, 0, 1);
  p.Finish();
}

void ParseTable(YamlSection t, TableConfig* out) {
  t.ReadDoubleList("center", &out->center, 2, -10, 10);
  t.ReadDoubleList("friction", &out->friction, 3, 0, 10);
  t.ReadDouble("wall_x", &out->wall_x, 0.01, 10);
  t.ReadDouble("wall_y_low", &out->wall_y_low, -10, 10);
  t.ReadDouble("wall_y_high", &out->wall_y_high, -10, 10);
  t.ReadDouble("wall_half_thickness", &out->wall_half_thickness, 1e-4, 1);
  t.ReadDouble("wall_half_height", &out->wall_half_height, 1e-3, 10);
  t.ReadDoubleList("object_low", &out->object_low, 2, -10, 10);
  t.ReadDoubleList("object_high", &out->object_high, 2, -10, 10);
  t.Finish();
}

void ParseHand(YamlSection h, HandConfig* out) {
  h.ReadDouble("action_scale", &out->action_scale, 1e-4, 1);
  h.ReadDouble("z", &out->z, 0, 1);
  h.ReadDoubleList("start", &out->start, 2, -10, 10);
  h.ReadDoubleList("mocap_low", &out->mocap_low, 2, -10, 10);
  h.ReadDoubleList("mocap_high", &out->mocap_high, 2, -10, 10);
  h.ReadDouble("weld_timeconst", &out->weld_timeconst, 1e-4, 1);
  h.ReadDouble("mass", &out->mass, 1e-4, 1e3);
  h.ReadDoubleList("half_size", &out->half_size, 3, 1e-4, 1);
  h.Finish();
}

void ParseSampling(YamlSection g, SamplingConfig* out) {
  g.ReadDoubleList("init_low", &out->init_low, 2, -10, 10);
  g.ReadDoubleList("init_high", &out->init_high, 2, -10, 10);
  g.ReadDouble("init_min_object_distance", &out->init_min_object_distance, 0, 1);
  g.ReadDouble("init_min_hand_distance", &out->init_min_hand_distance, 0, 1);
  g.ReadDoubleList("goal_low", &out->goal_low, 2, -10, 10);
  g.ReadDoubleList("goal_high", &out->goal_high, 2, -10, 10);
  g.ReadDouble("goal_min_object_distance", &out->goal_min_object_distance, 0, 1);
  g.ReadDouble("goal_min_hand_distance", &out->goal_min_hand_distance, 0, 1);
  g.ReadDoubleList("subgoal_low", &out->subgoal_low, 2, -10, 10);
  g.ReadDoubleList("subgoal_high", &out->subgoal_high, 2, -10, 10);
  g.ReadDouble("reference_radius", &out->reference_radius, 1e-4, 1);
  g.ReadBool("static_object_random_goal", &out->static_object_random_goal);
  g.ReadBool("tied_goal_in_box", &out->tied_goal_in_box);
  g.ReadInt("max_attempts", &out->max_attempts, 1, 100000000);
  g.Finish();
}

// Fails with a rule that involves several keys, naming the offending key under env: an item
// of objects or connections by its own line, anything else by its top-level key.
[[noreturn]] void FailWithProblem(YamlSection& s, const EnvConfigProblem& problem,
                                  std::vector<YamlSection>& object_items, std::vector<YamlSection>& connection_items) {
  for (auto& [name, items] :
       {std::pair{std::string("objects["), &object_items}, std::pair{std::string("connections["), &connection_items}}) {
    if (problem.key.rfind(name, 0) != 0) continue;
    const size_t close = problem.key.find(']');
    const size_t index = std::stoul(problem.key.substr(name.size(), close - name.size()));
    if (index >= items->size()) break;
    const std::string sub = close + 1 < problem.key.size() ? problem.key.substr(close + 2) : "";
    (*items)[index].FailRule(sub.empty() ? "objects" : sub, problem.message);
  }
  const std::string top = problem.key.substr(0, problem.key.find_first_of(".["));
  s.FailRule(top, (problem.key != top ? "at " + problem.key + ": " : std::string()) + problem.message);
}

}  // namespace

void ParseEnv(YamlSection s, EnvConfig* out) {
  std::vector<YamlSection> object_items, connection_items;
  if (s.Has("objects")) {
    // the list decides the number of pucks; num_pucks is read (and recorded) only when given
    if (s.Has("num_pucks")) s.ReadInt("num_pucks", &out->num_pucks, 1, 6);
    ParseItems(s, "objects", ParseObject, &out->objects, &object_items);
    if (out->objects.empty() || out->objects.size() > 6)
      s.FailRule("objects", "expected 1 to 6 objects, got " + std::to_string(out->objects.size()));
    if (s.Has("num_pucks") && out->num_pucks != static_cast<int>(out->objects.size()))
      s.FailRule("num_pucks",
                 "is " + std::to_string(out->num_pucks) + " but objects lists " + std::to_string(out->objects.size()));
    out->num_pucks = static_cast<int>(out->objects.size());
  } else {
    s.ReadInt("num_pucks", &out->num_pucks, 1, 6);
  }
  if (s.Has("connections")) ParseItems(s, "connections", ParseConnection, &out->connections, &connection_items);
  ParseObjectSets(s, "object_sets", &out->object_sets);
  ParseObjectSets(s, "eval_object_sets", &out->eval_object_sets);
  s.ReadBool("velocities", &out->velocities);
  s.ReadDouble("success_threshold", &out->success_threshold, 1e-6, 10);
  ParsePhysics(s.Child("physics"), &out->physics);
  ParseTable(s.Child("table"), &out->table);
  ParseHand(s.Child("hand"), &out->hand);
  ParseSampling(s.Child("sampling"), &out->sampling);
  if (EnvConfigProblem problem = CheckEnvConfig(*out); !problem.ok())
    FailWithProblem(s, problem, object_items, connection_items);
  s.Finish();
}

}  // namespace srics::config
