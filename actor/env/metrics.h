#pragma once
// Episode metrics as pure functions, shared by the environment and by anyone who holds
// positions and goals (evaluation, tests, the learner).

#include <span>

#include "actor/env/environment.h"

namespace srics::env {

// Distances of `positions` to `goals` (both arm first, same size >= 1):
// avg_distance = (hand + sum of objects) / N; avg_object_distance = sum of objects / (N - 1)
// (0 when there is no object); success = hand + sum of objects < N * success_threshold.
Metrics ComputeMetrics(std::span<const Vec2> positions, std::span<const Vec2> goals, double success_threshold);

}  // namespace srics::env
