#include "actor/env/metrics.h"

#include <cmath>
#include <stdexcept>

namespace srics::env {

Metrics ComputeMetrics(std::span<const Vec2> positions, std::span<const Vec2> goals, double success_threshold) {
  if (positions.empty() || positions.size() != goals.size())
    throw std::invalid_argument("ComputeMetrics: positions and goals need the same size >= 1");
  Metrics m;
  const size_t n = positions.size();
  m.distances.resize(n);
  double total = 0;
  for (size_t i = 0; i < n; ++i) {
    m.distances[i] = std::hypot(positions[i][0] - goals[i][0], positions[i][1] - goals[i][1]);
    total += m.distances[i];
  }
  m.hand_distance = m.distances[0];
  m.avg_distance = total / static_cast<double>(n);
  m.avg_object_distance = n > 1 ? (total - m.hand_distance) / static_cast<double>(n - 1) : 0.0;
  m.success = total < static_cast<double>(n) * success_threshold;
  return m;
}

}  // namespace srics::env
