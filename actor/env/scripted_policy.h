#pragma once
// Scripted controllers on entity positions: used by tests (physics checks), by the episode
// drawing command and as a sanity baseline. Pure functions, no MuJoCo.

#include "actor/env/types.h"
#include "common/config/env_config.h"

namespace srics::env {

// What the pushing controller needs to know about the bodies, and its own gains.
struct PushGeometry {
  double object_radius = 0;      // bounding radius of the pushed object
  double hand_half_width = 0;    // half width of the hand's footprint
  double action_scale = 0;       // metres per unit action (hand.action_scale)
  Vec2 hand_low{}, hand_high{};  // where the hand can go (hand.mocap_low/high)
  double clearance = 0.02;       // extra gap kept while walking around the object
  // largest action component while pushing: the weld makes the hand jump to each new mocap
  // target (peak speed ~36 x the step length per second), so a gentle push keeps the object
  // from being kicked away
  double push_speed = 0.2;
  // largest action component while moving close to the object (not pushing)
  double near_speed = 0.3;
  // the object counts as delivered within this distance of its goal: the hand stops
  double done_tolerance = 0.015;
};

// The geometry of catalogue object `entity` (1..n) and the hand of `config`.
PushGeometry MakePushGeometry(const config::EnvConfig& config, int entity);

// Action (each component in [-1, 1]) that moves the hand toward `target`.
Vec2 ReachAction(const Vec2& hand, const Vec2& target, double action_scale);

// Action of a simple pusher: walk around the object (never through it) to the side opposite
// its goal, line up behind it, then push it gently along the line to the goal.
Vec2 PushAction(const Vec2& hand, const Vec2& object, const Vec2& goal, const PushGeometry& g);

}  // namespace srics::env
