#pragma once
// Scripted controllers on entity positions: used by tests (physics checks), by the episode
// drawing command and as a sanity baseline. Pure functions, no MuJoCo.

#include "actor/env/types.h"

namespace srics::env {

// What the pushing controller needs to know about the bodies.
struct PushGeometry {
  double object_radius = 0.04;   // bounding radius of the pushed object
  double hand_half_width = 0.02; // half width of the hand's footprint
  double action_scale = 0.1;     // metres per unit action (hand.action_scale)
  double clearance = 0.02;       // extra gap kept while walking around the object
};

// Action (each component in [-1, 1]) that moves the hand toward `target`.
Vec2 ReachAction(const Vec2& hand, const Vec2& target, double action_scale);

// Action of a simple pusher: go around the object to the side opposite its goal, line up
// behind it, then push it along the line to the goal (slower near the goal).
Vec2 PushAction(const Vec2& hand, const Vec2& object, const Vec2& goal, const PushGeometry& g);

}  // namespace srics::env
