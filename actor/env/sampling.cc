#include "actor/env/sampling.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <string>

namespace srics::env {
namespace {

using config::EnvConfig;
using config::ObjectConfig;

// The connection that places entity `e` (it is its second object), or nullptr.
const config::ConnectionConfig* PlacingConnection(const EnvConfig& c, int e) {
  for (const auto& k : c.connections)
    if (k.second == e) return &k;
  return nullptr;
}

int IndexOf(std::span<const int> present, int e) {
  for (size_t k = 0; k < present.size(); ++k)
    if (present[k] == e) return static_cast<int>(k);
  return -1;
}

bool Inside(const Vec2& p, const Vec2& lo, const Vec2& hi) {
  return p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1];
}

// The spacing rules of one placement (initial positions or goals) of the objects `present`.
// Exemptions, each of a rule no draw could meet: objects marked `pinned` (a static object's
// goal kept at its start) from the hand and from each other, since they started under the
// looser initial rules and nothing moves them; a tied pair from the object spacing, since its
// tie sets their distance (goals exactly one link apart, starts within it; a 0.119 m spring
// between goals that had to keep 0.133 m failed every draw of random table 5): it only must
// not overlap.
struct SpacingRules {
  SpacingRules(const EnvConfig& c, std::span<const int> present, std::span<const double> radius, double object_base,
               double hand_base, std::vector<bool> pinned)
      : s(c.sampling),
        radius(radius),
        hand{c.hand.start[0], c.hand.start[1]},
        object_base(object_base),
        hand_base(hand_base),
        pinned(std::move(pinned)),
        tied(present.size() * present.size(), false) {
    const size_t n = present.size();
    for (const auto& link : c.connections) {
      const int a = IndexOf(present, link.first), b = IndexOf(present, link.second);
      if (a >= 0 && b >= 0) tied[a * n + b] = tied[b * n + a] = true;
    }
  }
  bool HandKept(size_t k, const Vec2& p) const {
    return pinned[k] || Distance(p, hand) >= hand_base + std::max(0.0, radius[k] - s.reference_radius);
  }
  bool PairKept(size_t i, const Vec2& pi, size_t j, const Vec2& pj) const {
    if (pinned[i] && pinned[j]) return true;
    if (tied[i * radius.size() + j]) return Distance(pi, pj) >= radius[i] + radius[j];
    return Distance(pi, pj) >= RequiredDistance(s, object_base, radius[i], radius[j]);
  }
  // every object against the hand and every pair
  bool Hold(std::span<const Vec2> pos) const {
    for (size_t i = 0; i < pos.size(); ++i) {
      if (!HandKept(i, pos[i])) return false;
      for (size_t j = 0; j < i; ++j)
        if (!PairKept(i, pos[i], j, pos[j])) return false;
    }
    return true;
  }

  const config::SamplingConfig& s;
  std::span<const double> radius;
  Vec2 hand;
  double object_base, hand_base;
  std::vector<bool> pinned;
  std::vector<bool> tied;  // n x n
};

std::string SetText(std::span<const int> present) {
  std::string text = "[";
  for (size_t k = 0; k < present.size(); ++k) text += (k ? ", " : "") + std::to_string(present[k]);
  return text + "]";
}

// Fallback for crowded tables, where whole draws rarely keep every spacing rule (different-6's
// six goals: about one whole draw in 10,000, so 100,000 draws failed now and then and the
// actor died). Objects are placed one at a time in `order`, each redrawn (`draw`: nullopt when
// it left its box) until it keeps its distance from the hand and the objects placed before it;
// all start again when one cannot be placed. Same rules, a somewhat different distribution:
// tables whose whole draws succeed never come here, so their samples are unchanged.
bool PlaceOneByOne(const SpacingRules& rules, std::span<const size_t> order,
                   const std::function<std::optional<Vec2>(size_t)>& draw, std::vector<Vec2>& pos) {
  // a crowded table jams now and then (different-6: 3 restarts in 10 fail to place all six
  // goals), an object stuck for 100 draws rarely finds room later: restart instead
  constexpr int kDrawsPerObject = 100;
  const int restarts = std::max(10, rules.s.max_attempts / kDrawsPerObject);
  for (int restart = 0; restart < restarts; ++restart) {
    size_t placed = 0;
    for (; placed < order.size(); ++placed) {
      const size_t k = order[placed];
      bool fits = false;
      for (int d = 0; d < kDrawsPerObject && !fits; ++d) {
        const std::optional<Vec2> p = draw(k);
        fits = p && rules.HandKept(k, *p);
        for (size_t m = 0; m < placed && fits; ++m) fits = rules.PairKept(k, *p, order[m], pos[order[m]]);
        if (fits) pos[k] = *p;
      }
      if (!fits) break;
    }
    if (placed == order.size()) return true;
  }
  return false;
}

// The order PlaceOneByOne needs: objects that cannot move (`pinned`) first, then the other
// untied ones, then tied ones after the object they hang on (connection order).
std::vector<size_t> PlacingOrder(const EnvConfig& c, std::span<const int> present,
                                 const std::function<bool(size_t)>& pinned) {
  std::vector<size_t> order;
  for (int pass = 0; pass < 2; ++pass)
    for (size_t k = 0; k < present.size(); ++k)
      if (PlacingConnection(c, present[k]) == nullptr && pinned(k) == (pass == 0)) order.push_back(k);
  for (const auto& link : c.connections)
    if (IndexOf(present, link.first) >= 0 && IndexOf(present, link.second) >= 0)
      order.push_back(static_cast<size_t>(IndexOf(present, link.second)));
  return order;
}

}  // namespace

std::vector<int> SampleObjectSet(const EnvConfig& config, bool eval, Rng& rng) {
  const auto& sets = (eval && !config.eval_object_sets.empty()) ? config.eval_object_sets : config.object_sets;
  std::vector<int> chosen;
  if (sets.empty()) {
    const int n = static_cast<int>(config::EffectiveObjects(config).size());
    for (int e = 1; e <= n; ++e) chosen.push_back(e);
  } else {
    chosen = sets[sets.size() == 1 ? 0 : UniformIndex(rng, sets.size())];
    std::sort(chosen.begin(), chosen.end());
  }
  return chosen;
}

double RequiredDistance(const config::SamplingConfig& s, double base, double ra, double rb) {
  return base + std::max(0.0, ra - s.reference_radius) + std::max(0.0, rb - s.reference_radius);
}

void ObjectBox(const EnvConfig& c, const std::vector<double>& low, const std::vector<double>& high, double r, Vec2* lo,
               Vec2* hi) {
  const auto& t = c.table;
  (*lo)[0] = std::max(low[0], -t.wall_x + t.wall_half_thickness + r);
  (*hi)[0] = std::min(high[0], t.wall_x - t.wall_half_thickness - r);
  (*lo)[1] = std::max(low[1], t.wall_y_low + t.wall_half_thickness + r);
  (*hi)[1] = std::min(high[1], t.wall_y_high - t.wall_half_thickness - r);
}

namespace {

// Each present object's bounding radius and sampling box (`low`..`high` within the walls).
struct ObjectBoxes {
  ObjectBoxes(const EnvConfig& c, const std::vector<ObjectConfig>& objects, std::span<const int> present,
              const std::vector<double>& low, const std::vector<double>& high)
      : radius(present.size()), lo(present.size()), hi(present.size()) {
    for (size_t k = 0; k < present.size(); ++k) {
      radius[k] = config::BoundingRadius(objects.at(present[k] - 1));
      ObjectBox(c, low, high, radius[k], &lo[k], &hi[k]);
    }
  }
  std::vector<double> radius;
  std::vector<Vec2> lo, hi;
};

}  // namespace

std::vector<Vec2> SampleInitialPositions(const EnvConfig& c, std::span<const int> present, Rng& rng) {
  const std::vector<ObjectConfig> objects = config::EffectiveObjects(c);
  const size_t n = present.size();
  const ObjectBoxes boxes(c, objects, present, c.sampling.init_low, c.sampling.init_high);
  // named references, not a structured binding: the placement lambdas capture them (C++20
  // allows capturing bindings; clang 14 of the sanitizer build does not)
  const auto& radius = boxes.radius;
  const auto& lo = boxes.lo;
  const auto& hi = boxes.hi;
  std::vector<Vec2> pos(n);
  const SpacingRules rules(c, present, radius, c.sampling.init_min_object_distance, c.sampling.init_min_hand_distance,
                           std::vector<bool>(n, false));
  for (int attempt = 0; attempt < c.sampling.max_attempts; ++attempt) {
    // free and fixed objects first
    for (size_t k = 0; k < n; ++k) {
      const ObjectConfig& o = objects[present[k] - 1];
      if (PlacingConnection(c, present[k]) != nullptr) continue;
      if (!o.fixed_position.empty()) {
        pos[k] = {o.fixed_position[0], o.fixed_position[1]};
      } else {
        pos[k] = {Uniform(rng, lo[k][0], hi[k][0]), Uniform(rng, lo[k][1], hi[k][1])};
      }
    }
    // tied objects start within their link's length of the object they hang on
    bool inside = true;
    for (const auto& link : c.connections) {
      const int k2 = IndexOf(present, link.second);
      const int k1 = IndexOf(present, link.first);
      if (k2 < 0 || k1 < 0) continue;
      const double closest = RequiredDistance(c.sampling, c.sampling.init_min_object_distance, radius[k1], radius[k2]);
      const double r = Uniform(rng, std::min(closest, link.length), link.length);
      const double phi = Uniform(rng, 0, 2 * std::numbers::pi);
      pos[k2] = {pos[k1][0] + r * std::sin(phi), pos[k1][1] + r * std::cos(phi)};
      inside = inside && Inside(pos[k2], lo[k2], hi[k2]);
    }
    if (inside && rules.Hold(pos)) return pos;
  }
  // one object at a time (crowded tables)
  const auto order =
      PlacingOrder(c, present, [&](size_t k) { return !objects[present[k] - 1].fixed_position.empty(); });
  const auto draw = [&](size_t k) -> std::optional<Vec2> {
    const ObjectConfig& o = objects[present[k] - 1];
    if (const auto* link = PlacingConnection(c, present[k])) {
      const int k1 = IndexOf(present, link->first);
      const double closest = RequiredDistance(c.sampling, c.sampling.init_min_object_distance, radius[k1], radius[k]);
      const double r = Uniform(rng, std::min(closest, link->length), link->length);
      const double phi = Uniform(rng, 0, 2 * std::numbers::pi);
      const Vec2 p{pos[k1][0] + r * std::sin(phi), pos[k1][1] + r * std::cos(phi)};
      return Inside(p, lo[k], hi[k]) ? std::optional<Vec2>(p) : std::nullopt;
    }
    if (!o.fixed_position.empty()) return Vec2{o.fixed_position[0], o.fixed_position[1]};
    return Vec2{Uniform(rng, lo[k][0], hi[k][0]), Uniform(rng, lo[k][1], hi[k][1])};
  };
  if (PlaceOneByOne(rules, order, draw, pos)) return pos;
  throw SamplingError("no initial placement of objects " + SetText(present) + " within " +
                      std::to_string(c.sampling.max_attempts) +
                      " attempts: the objects do not fit with the spacing rules");
}

std::vector<Vec2> SampleGoals(const EnvConfig& c, std::span<const int> present, std::span<const Vec2> initial,
                              Rng& rng) {
  const std::vector<ObjectConfig> objects = config::EffectiveObjects(c);
  const size_t n = present.size();
  if (initial.size() != n) throw std::invalid_argument("SampleGoals: one initial xy per object");
  const ObjectBoxes boxes(c, objects, present, c.sampling.goal_low, c.sampling.goal_high);
  // named references, not a structured binding: the placement lambdas capture them (C++20
  // allows capturing bindings; clang 14 of the sanitizer build does not)
  const auto& radius = boxes.radius;
  const auto& lo = boxes.lo;
  const auto& hi = boxes.hi;
  const Vec2 hand{c.hand.start[0], c.hand.start[1]};
  std::vector<Vec2> goals(n + 1);
  goals[0] = hand;
  std::span<Vec2> objects_goals(goals.data() + 1, n);
  std::vector<bool> pinned(n);
  for (size_t k = 0; k < n; ++k) pinned[k] = objects[present[k] - 1].is_static && !c.sampling.static_object_random_goal;
  const SpacingRules rules(c, present, radius, c.sampling.goal_min_object_distance, c.sampling.goal_min_hand_distance,
                           pinned);
  for (int attempt = 0; attempt < c.sampling.max_attempts; ++attempt) {
    for (size_t k = 0; k < n; ++k) {
      const ObjectConfig& o = objects[present[k] - 1];
      if (PlacingConnection(c, present[k]) != nullptr) continue;
      if (pinned[k]) {
        objects_goals[k] = initial[k];
      } else {
        objects_goals[k] = {Uniform(rng, lo[k][0], hi[k][0]), Uniform(rng, lo[k][1], hi[k][1])};
      }
    }
    // the tied object's goal is the link's length away, at one random angle per draw
    const double phi = Uniform(rng, 0, 2 * std::numbers::pi);
    bool inside = true;
    for (const auto& link : c.connections) {
      const int k2 = IndexOf(present, link.second);
      const int k1 = IndexOf(present, link.first);
      if (k2 < 0 || k1 < 0) continue;
      objects_goals[k2] = {objects_goals[k1][0] + link.length * std::sin(phi),
                           objects_goals[k1][1] + link.length * std::cos(phi)};
      if (c.sampling.tied_goal_in_box) inside = inside && Inside(objects_goals[k2], lo[k2], hi[k2]);
    }
    if (inside && rules.Hold(objects_goals)) return goals;
  }
  // one object at a time (crowded tables)
  const auto order = PlacingOrder(c, present, [&](size_t k) { return pinned[k]; });
  std::vector<Vec2> placed(n);
  const auto draw = [&](size_t k) -> std::optional<Vec2> {
    if (const auto* link = PlacingConnection(c, present[k])) {
      const Vec2& anchor = placed[IndexOf(present, link->first)];
      const double phi = Uniform(rng, 0, 2 * std::numbers::pi);
      const Vec2 p{anchor[0] + link->length * std::sin(phi), anchor[1] + link->length * std::cos(phi)};
      if (c.sampling.tied_goal_in_box && !Inside(p, lo[k], hi[k])) return std::nullopt;
      return p;
    }
    if (pinned[k]) return initial[k];
    return Vec2{Uniform(rng, lo[k][0], hi[k][0]), Uniform(rng, lo[k][1], hi[k][1])};
  };
  if (PlaceOneByOne(rules, order, draw, placed)) {
    std::copy(placed.begin(), placed.end(), objects_goals.begin());
    return goals;
  }
  throw SamplingError("no goal placement of objects " + SetText(present) + " within " +
                      std::to_string(c.sampling.max_attempts) +
                      " attempts: the objects do not fit with the spacing rules");
}

Vec2 SampleSubgoal(const config::SamplingConfig& s, Rng& rng) {
  return {Uniform(rng, s.subgoal_low[0], s.subgoal_high[0]), Uniform(rng, s.subgoal_low[1], s.subgoal_high[1])};
}

}  // namespace srics::env
