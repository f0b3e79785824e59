#include "actor/env/scripted_policy.h"

#include <algorithm>
#include <cmath>

namespace srics::env {

Vec2 ReachAction(const Vec2& hand, const Vec2& target, double action_scale) {
  return {std::clamp((target[0] - hand[0]) / action_scale, -1.0, 1.0),
          std::clamp((target[1] - hand[1]) / action_scale, -1.0, 1.0)};
}

Vec2 PushAction(const Vec2& hand, const Vec2& object, const Vec2& goal, const PushGeometry& g) {
  const double gx = goal[0] - object[0], gy = goal[1] - object[1];
  const double to_goal = std::hypot(gx, gy);
  if (to_goal < 1e-3) return {0, 0};
  const Vec2 dir{gx / to_goal, gy / to_goal};
  const double contact = g.object_radius + g.hand_half_width;
  // hand relative to the object: along the push line and across it
  const double rx = hand[0] - object[0], ry = hand[1] - object[1];
  const double along = rx * dir[0] + ry * dir[1];
  const Vec2 across{rx - along * dir[0], ry - along * dir[1]};
  const double across_norm = std::hypot(across[0], across[1]);

  // not behind the object yet: step out to the side the hand is on, then back past it
  const double reach = contact + g.clearance;
  if (along > -contact) {
    const Vec2 side = across_norm > 1e-6 ? Vec2{across[0] / across_norm, across[1] / across_norm}
                                         : Vec2{-dir[1], dir[0]};
    if (across_norm < contact + 0.5 * g.clearance)
      return ReachAction(hand,
                         {object[0] + side[0] * reach + dir[0] * along,
                          object[1] + side[1] * reach + dir[1] * along},
                         g.action_scale);
    return ReachAction(hand,
                       {object[0] + side[0] * reach - dir[0] * reach,
                        object[1] + side[1] * reach - dir[1] * reach},
                       g.action_scale);
  }
  // behind but off the line: line up
  if (across_norm > 0.01) {
    const double back = contact + 0.5 * g.clearance;
    return ReachAction(hand, {object[0] - dir[0] * back, object[1] - dir[1] * back},
                       g.action_scale);
  }
  // push: the hand aims at the point behind the goal, moving at most half speed
  const Vec2 target{goal[0] - dir[0] * contact, goal[1] - dir[1] * contact};
  Vec2 a = ReachAction(hand, target, g.action_scale);
  return {std::clamp(a[0], -0.5, 0.5), std::clamp(a[1], -0.5, 0.5)};
}

}  // namespace srics::env
