#include "actor/env/scripted_policy.h"

#include <algorithm>
#include <cmath>

namespace srics::env {
namespace {

// Scales `a` down so that its largest component is at most `limit`.
Vec2 Limit(const Vec2& a, double limit) {
  const double m = std::max(std::abs(a[0]), std::abs(a[1]));
  return m > limit ? Vec2{a[0] * limit / m, a[1] * limit / m} : a;
}

// Distance from point p to the segment a-b.
double SegmentDistance(const Vec2& a, const Vec2& b, const Vec2& p) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
}

bool Reachable(const Vec2& p, const PushGeometry& g) {
  return p[0] >= g.hand_low[0] && p[0] <= g.hand_high[0] && p[1] >= g.hand_low[1] && p[1] <= g.hand_high[1];
}

}  // namespace

PushGeometry MakePushGeometry(const config::EnvConfig& config, int entity) {
  PushGeometry g;
  g.object_radius = config::BoundingRadius(config::EffectiveObjects(config).at(entity - 1));
  g.hand_half_width = std::max(config.hand.half_size[0], config.hand.half_size[1]);
  g.action_scale = config.hand.action_scale;
  g.hand_low = {config.hand.mocap_low[0], config.hand.mocap_low[1]};
  g.hand_high = {config.hand.mocap_high[0], config.hand.mocap_high[1]};
  return g;
}

Vec2 ReachAction(const Vec2& hand, const Vec2& target, double action_scale) {
  return {std::clamp((target[0] - hand[0]) / action_scale, -1.0, 1.0),
          std::clamp((target[1] - hand[1]) / action_scale, -1.0, 1.0)};
}

Vec2 PushAction(const Vec2& hand, const Vec2& object, const Vec2& goal, const PushGeometry& g) {
  const double to_goal = Distance(goal, object);
  if (to_goal < g.done_tolerance) return {0, 0};
  const Vec2 dir{(goal[0] - object[0]) / to_goal, (goal[1] - object[1]) / to_goal};
  const Vec2 perp{-dir[1], dir[0]};
  const double contact = g.object_radius + g.hand_half_width;
  const double reach = contact + g.clearance;
  // close to the object, move slowly: a fast hand kicks it away
  const double limit = Distance(hand, object) < reach + 2 * g.clearance ? g.near_speed : 1.0;

  // hand relative to the object: along the push line and across it
  const double rx = hand[0] - object[0], ry = hand[1] - object[1];
  const double along = rx * dir[0] + ry * dir[1];
  const double across = rx * perp[0] + ry * perp[1];

  // behind and on the line: push, aiming at the point behind the goal
  if (along < -0.5 * contact && std::abs(across) < 0.01) {
    const Vec2 target{goal[0] - dir[0] * contact, goal[1] - dir[1] * contact};
    return Limit(ReachAction(hand, target, g.action_scale), g.push_speed);
  }
  // the lining-up point behind the object, if the way there is clear
  const double back = contact + 0.5 * g.clearance;
  const Vec2 behind{object[0] - dir[0] * back, object[1] - dir[1] * back};
  if (SegmentDistance(hand, behind, object) >= contact) return Limit(ReachAction(hand, behind, g.action_scale), limit);
  // otherwise orbit the object at distance `reach`, 45 degrees at a time, the short way
  // round unless that way leaves the hand's box
  const double r = std::max(Distance(hand, object), 1e-6);
  if (r < reach - 0.5 * g.clearance)  // too close: step straight out first
    return Limit(ReachAction(hand, {object[0] + rx / r * reach, object[1] + ry / r * reach}, g.action_scale), limit);
  const double pi = 3.14159265358979323846;
  const double at = std::atan2(ry, rx);
  double delta = std::atan2(-dir[1], -dir[0]) - at;
  while (delta > pi) delta -= 2 * pi;
  while (delta <= -pi) delta += 2 * pi;
  const auto arc_reachable = [&](double sweep) {
    for (int k = 1; k <= 12; ++k) {
      const double a = at + sweep * k / 12;
      if (!Reachable({object[0] + reach * std::cos(a), object[1] + reach * std::sin(a)}, g)) return false;
    }
    return true;
  };
  double sweep = delta;
  if (!arc_reachable(sweep)) {
    const double other = delta > 0 ? delta - 2 * pi : delta + 2 * pi;
    if (arc_reachable(other)) sweep = other;
  }
  const double step = std::clamp(sweep, -pi / 4, pi / 4);
  Vec2 target{object[0] + reach * std::cos(at + step), object[1] + reach * std::sin(at + step)};
  target[0] = std::clamp(target[0], g.hand_low[0], g.hand_high[0]);
  target[1] = std::clamp(target[1], g.hand_low[1], g.hand_high[1]);
  return Limit(ReachAction(hand, target, g.action_scale), limit);
}

}  // namespace srics::env
