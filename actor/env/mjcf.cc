#include "actor/env/mjcf.h"

#include <ostream>
#include <sstream>

namespace srics::env {
namespace {

using config::ConnectionKind;
using config::ObjectShape;

// Collision bits: objects touch everything; the hand touches objects and walls but not the
// table (it hovers at hand.z); walls and table are world geoms (never collide with each other).
constexpr int kObjectType = 1, kObjectAffinity = 3;
constexpr int kHandType = 2, kHandAffinity = 0;
constexpr int kTableType = 0, kTableAffinity = 1;
constexpr int kWallType = 0, kWallAffinity = 3;

// Six distinct hues (display only).
constexpr double kPalette[6][3] = {{0.18, 0.83, 0.21}, {0.21, 0.18, 0.83}, {0.83, 0.21, 0.18},
                                   {0.18, 0.79, 0.83}, {0.83, 0.18, 0.79}, {0.79, 0.83, 0.18}};

std::string Join(const std::vector<double>& v) {
  std::ostringstream out;
  out.precision(17);
  for (size_t i = 0; i < v.size(); ++i) out << (i ? " " : "") << v[i];
  return out.str();
}

}  // namespace

Vec2 ParkingPosition(const config::EnvConfig& config, int entity) {
  // far from the table and 0.5 m from each other; a tied object waits next to the object it
  // hangs on, inside its link's length, so that parked links pull on nothing
  for (const auto& k : config.connections) {
    if (k.second == entity) {
      const Vec2 first = ParkingPosition(config, k.first);
      return {first[0], first[1] + 0.95 * k.length};
    }
  }
  return {-10.0 - 0.5 * entity, 0.0};
}

std::array<double, 3> ObjectColor(const config::EnvConfig& config, int entity) {
  const auto objects = config::EffectiveObjects(config);
  const auto& rgb = objects.at(entity - 1).rgb;
  if (rgb.size() == 3) return {rgb[0], rgb[1], rgb[2]};
  const double* p = kPalette[(entity - 1) % 6];
  return {p[0], p[1], p[2]};
}

namespace {

// The model's options and defaults, and the opening of the world body.
void WriteHeader(std::ostream& x, const config::EnvConfig& c) {
  x << "<mujoco model=\"rearrange\">\n"
    << "  <compiler angle=\"radian\" inertiafromgeom=\"auto\"/>\n"
    << "  <option timestep=\"" << c.physics.timestep << "\" integrator=\"Euler\" iterations=\""
    << c.physics.solver_iterations << "\">\n";
  // A fixed static object is a mocap body, welded to the world like the table; the parent
  // filter would drop its contacts with the hand and the objects (children of the world). Every
  // other body here is a child of the world already, so the flag changes nothing else.
  if (c.physics.static_objects == config::StaticObjects::kFixed) x << "    <flag filterparent=\"disable\"/>\n";
  x << "  </option>\n"
    << "  <size njmax=\"500\" nconmax=\"200\"/>\n"
    << "  <visual><headlight ambient=\"0.5 0.5 0.5\"/></visual>\n"
    << "  <default>\n"
    << "    <geom solref=\"" << Join(c.physics.geom_solref) << "\" solimp=\"" << Join(c.physics.geom_solimp)
    << "\" margin=\"" << c.physics.geom_margin << "\"/>\n"
    << "  </default>\n"
    << "  <worldbody>\n"
    << "    <light directional=\"true\" pos=\"0 0.6 1.5\" dir=\"0 0 -1\"/>\n";
}

// The table plane and the four invisible walls.
void WriteTableAndWalls(std::ostream& x, const config::TableConfig& t) {
  x << "    <geom name=\"table\" type=\"plane\" pos=\"" << t.center[0] << " " << t.center[1]
    << " 0\" size=\"0.4 0.25 0.5\" rgba=\".9 .9 .9 1\" friction=\"" << Join(t.friction) << "\" contype=\"" << kTableType
    << "\" conaffinity=\"" << kTableAffinity << "\"/>\n";
  const double wx = t.wall_x, th = t.wall_half_thickness, wh = t.wall_half_height;
  const double y_mid = 0.5 * (t.wall_y_low + t.wall_y_high);
  const double y_half = 0.5 * (t.wall_y_high - t.wall_y_low) + th;
  auto wall = [&](const char* name, double px, double py, double sx, double sy) {
    x << "    <geom name=\"" << name << "\" type=\"box\" pos=\"" << px << " " << py << " " << wh << "\" size=\"" << sx
      << " " << sy << " " << wh << "\" rgba=\".6 .6 .5 0\" friction=\"" << Join(t.friction) << "\" contype=\""
      << kWallType << "\" conaffinity=\"" << kWallAffinity << "\"/>\n";
  };
  wall("wall_x_low", -wx, y_mid, th, y_half);
  wall("wall_x_high", wx, y_mid, th, y_half);
  wall("wall_y_low", 0, t.wall_y_low, wx + th, th);
  wall("wall_y_high", 0, t.wall_y_high, wx + th, th);
}

// The hand and the mocap body it follows (through the weld of WriteEqualityAndTendons).
void WriteHand(std::ostream& x, const config::HandConfig& h) {
  x << "    <body name=\"mocap\" mocap=\"true\" pos=\"" << h.start[0] << " " << h.start[1] << " " << h.z << "\"/>\n"
    << "    <body name=\"hand\" pos=\"" << h.start[0] << " " << h.start[1] << " " << h.z << "\">\n"
    << "      <freejoint name=\"hand\"/>\n"
    << "      <geom name=\"hand\" type=\"box\" size=\"" << Join(h.half_size) << "\" mass=\"" << h.mass
    << "\" rgba=\"0.2 0.2 0.2 1\" contype=\"" << kHandType << "\" conaffinity=\"" << kHandAffinity << "\"/>\n"
    << "    </body>\n";
}

// One body per object, parked: Reset places the ones present.
void WriteObjects(std::ostream& x, const config::EnvConfig& c) {
  const auto objects = config::EffectiveObjects(c);
  for (size_t i = 0; i < objects.size(); ++i) {
    const auto& o = objects[i];
    const int e = static_cast<int>(i) + 1;
    const Vec2 park = ParkingPosition(c, e);
    const auto rgb = ObjectColor(c, e);
    // a fixed static object is a mocap body: no joint, placed by the env at reset
    const bool fixed = o.is_static && c.physics.static_objects == config::StaticObjects::kFixed;
    x << "    <body name=\"object" << e << "\" pos=\"" << park[0] << " " << park[1] << " " << o.half_height << "\""
      << (fixed ? " mocap=\"true\"" : "") << ">\n";
    if (!fixed) x << "      <freejoint name=\"object" << e << "\"/>\n";
    x << "      <inertial pos=\"0 0 0\" mass=\"" << o.mass << "\" diaginertia=\"" << o.inertia << " " << o.inertia
      << " " << o.inertia << "\"/>\n";
    if (o.shape == ObjectShape::kBox) {
      x << "      <geom name=\"object" << e << "\" type=\"box\" size=\"" << o.size << " " << o.size << " "
        << o.half_height << "\"";
    } else {
      x << "      <geom name=\"object" << e << "\" type=\"cylinder\" size=\"" << o.size << " " << o.half_height << "\"";
    }
    // a fixed object is stiff: with the default contacts the hand's weld pulls the hand through
    // it (the mocap target runs up to 10 cm ahead); solmix makes its parameters win in a contact
    if (fixed)
      x << " solref=\"" << Join(c.physics.fixed_object_solref) << "\" solimp=\"" << Join(c.physics.fixed_object_solimp)
        << "\" solmix=\"1000\"";
    x << " rgba=\"" << rgb[0] << " " << rgb[1] << " " << rgb[2] << " 1\" contype=\"" << kObjectType
      << "\" conaffinity=\"" << kObjectAffinity << "\"/>\n"
      << "      <site name=\"site" << e << "\" pos=\"0 0 0\" size=\"0.01\"/>\n"
      << "    </body>\n";
  }
}

// The hand's weld to the mocap body, and one tendon per connection (rope or spring).
void WriteEqualityAndTendons(std::ostream& x, const config::EnvConfig& c) {
  x << "  <equality>\n"
    << "    <weld body1=\"mocap\" body2=\"hand\" solref=\"" << c.hand.weld_timeconst
    << " 1\" relpose=\"0 0 0 1 0 0 0\"/>\n"
    << "  </equality>\n";
  if (c.connections.empty()) return;
  x << "  <tendon>\n";
  for (const auto& k : c.connections) {
    if (k.kind == ConnectionKind::kRope) {
      x << "    <spatial limited=\"true\" range=\"0 " << k.length << "\" solreflimit=\"" << k.limit_timeconst
        << " 1\" width=\"0.005\">\n";
    } else {
      x << "    <spatial stiffness=\"" << k.stiffness << "\" damping=\"" << k.damping << "\" springlength=\""
        << k.length << "\" width=\"0.005\">\n";
    }
    x << "      <site site=\"site" << k.first << "\"/>\n"
      << "      <site site=\"site" << k.second << "\"/>\n"
      << "    </spatial>\n";
  }
  x << "  </tendon>\n";
}

}  // namespace

std::string GenerateRearrangeMjcf(const config::EnvConfig& c) {
  std::ostringstream x;
  x.precision(17);
  WriteHeader(x, c);
  WriteTableAndWalls(x, c.table);
  WriteHand(x, c.hand);
  WriteObjects(x, c);
  x << "  </worldbody>\n";
  WriteEqualityAndTendons(x, c);
  x << "</mujoco>\n";
  return x.str();
}

}  // namespace srics::env
