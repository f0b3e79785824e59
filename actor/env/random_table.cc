#include "actor/env/random_table.h"

#include <cstdio>
#include <random>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace srics::env {
namespace {

// Portable draws: the standard distributions are not specified bit for bit across libraries,
// so the table of a seed is built from the raw 64-bit engine output only.
class Draw {
 public:
  explicit Draw(uint64_t seed) : engine_(seed * 0x9E3779B97F4A7C15ull + 0x7AB1E) {}
  double Uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  bool Chance(double p) { return Uniform(0, 1) < p; }
  int Int(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(engine_() % static_cast<uint64_t>(hi - lo + 1));
  }
  // rounded to a millimetre / gram so that the preset file reads back exactly
  double Rounded(double lo, double hi, double step) {
    return static_cast<double>(static_cast<int64_t>(Uniform(lo, hi) / step + 0.5)) * step;
  }

 private:
  std::mt19937_64 engine_;
};

config::EnvConfig DrawTable(Draw& d, const RandomTableOptions& o) {
  config::EnvConfig c;
  const int n = d.Int(o.min_objects, o.max_objects);
  c.num_pucks = n;
  std::vector<int> movable;
  for (int i = 0; i < n; ++i) {
    config::ObjectConfig obj;
    obj.shape = d.Chance(o.box_probability) ? config::ObjectShape::kBox : config::ObjectShape::kCylinder;
    obj.size = d.Rounded(o.min_size, o.max_size, 0.001);
    obj.mass = d.Rounded(o.min_mass, o.max_mass, 0.01);
    obj.is_static = d.Chance(o.static_probability);
    c.objects.push_back(obj);
  }
  for (int i = 0; i < n; ++i)
    if (!c.objects[i].is_static) movable.push_back(i + 1);
  // at least two movable objects: the first static ones become movable again
  for (int i = 0; i < n && movable.size() < 2; ++i) {
    if (!c.objects[i].is_static) continue;
    c.objects[i].is_static = false;
    movable.push_back(i + 1);
  }
  std::vector<std::pair<int, int>> pairs;
  for (size_t a = 0; a < movable.size(); ++a)
    for (size_t b = a + 1; b < movable.size(); ++b) pairs.emplace_back(movable[a], movable[b]);
  const double r = d.Uniform(0, 1);
  size_t ties = r < o.two_ties_probability ? 2 : r < o.two_ties_probability + o.one_tie_probability ? 1 : 0;
  while (ties-- > 0 && !pairs.empty()) {
    const int pick = d.Int(0, static_cast<int>(pairs.size()) - 1);
    config::ConnectionConfig tie;
    tie.first = pairs[pick].first;
    tie.second = pairs[pick].second;
    tie.kind = d.Chance(o.spring_probability) ? config::ConnectionKind::kSpring : config::ConnectionKind::kRope;
    tie.length = d.Rounded(o.min_tie_length, o.max_tie_length, 0.001);
    if (tie.kind == config::ConnectionKind::kSpring) tie.stiffness = d.Rounded(o.min_stiffness, o.max_stiffness, 1);
    c.connections.push_back(tie);
    // an object takes part in one tie at most (the goal rule places a tied object's goal from
    // its partner's)
    std::vector<std::pair<int, int>> rest;
    for (const auto& p : pairs)
      if (p.first != tie.first && p.first != tie.second && p.second != tie.first && p.second != tie.second)
        rest.push_back(p);
    pairs = std::move(rest);
  }
  return c;
}

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

config::EnvConfig RandomTable(uint64_t seed, const RandomTableOptions& options) {
  Draw d(seed);
  std::string last;
  for (int attempt = 0; attempt < options.max_attempts; ++attempt) {
    config::EnvConfig table = DrawTable(d, options);
    const config::EnvConfigProblem problem = config::CheckEnvConfig(table);
    if (problem.ok()) return table;
    last = problem.key + ": " + problem.message;
  }
  throw std::runtime_error("no random table of seed " + std::to_string(seed) + " passed the config rules in " +
                           std::to_string(options.max_attempts) + " draws (last: " + last + ")");
}

std::string RandomTableYaml(const config::EnvConfig& table, uint64_t seed, const std::string& graph) {
  std::ostringstream s;
  s << "# Random table " << seed << " (srics random-table --seed " << seed << ")\n";
  s << "# graph by construction: " << graph << "\n";
  s << "env:\n  objects:\n";
  for (const config::ObjectConfig& o : config::EffectiveObjects(table)) {
    s << "    - {shape: " << config::ShapeName(o.shape) << ", size: " << Number(o.size) << ", mass: " << Number(o.mass)
      << (o.is_static ? ", static: true" : "") << "}\n";
  }
  if (!table.connections.empty()) {
    s << "  connections:\n";
    for (const config::ConnectionConfig& k : table.connections) {
      const bool spring = k.kind == config::ConnectionKind::kSpring;
      s << "    - {objects: [" << k.first << ", " << k.second << "], kind: " << (spring ? "spring" : "rope")
        << ", length: " << Number(k.length);
      if (spring) s << ", stiffness: " << Number(k.stiffness) << ", damping: " << Number(k.damping);
      s << "}\n";
    }
  }
  return s.str();
}

}  // namespace srics::env
