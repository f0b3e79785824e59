#pragma once
// The graph service's training progress on stdout, for the development tools (toy_learn,
// graph_probe).

#include <cmath>
#include <cstdio>

#include "graph_service/service.h"

namespace srics::graph_service::testing {

// One training report: losses and graph, the mean edge weights row by row, each entity's
// loss against the zero-motion baseline. Other phases print nothing.
inline void PrintTrainingProgress(const Progress& p) {
  if (p.phase != Progress::Phase::kTraining) return;
  std::printf("%7.1fs upd %6lld train %.3g held %.3g (zero %.3g)  %s\n   ", p.elapsed_seconds,
              static_cast<long long>(p.updates), p.train_loss, p.held_out_loss, p.held_out_zero_loss, p.graph.c_str());
  const int n = static_cast<int>(std::sqrt(p.edge_scores.size()) + 0.5);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) std::printf(" %.3f", p.edge_scores[i * n + j]);
    std::printf(" |");
  }
  std::printf("\n    entity mse/zero:");
  for (int i = 0; i < n; ++i) std::printf(" %.2g/%.2g", p.entity_loss[i], p.entity_zero_loss[i]);
  std::printf("\n");
  std::fflush(stdout);
}

}  // namespace srics::graph_service::testing
