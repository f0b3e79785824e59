#pragma once
// What the learner tests share: synthetic episodes (entities walk deterministically from a
// seed), a small run's config and the process's resident memory.

#include <fstream>
#include <random>
#include <string>

#include "common/config/config.h"
#include "common/rl/agent_shape.h"
#include "common/rl/episode.h"
#include "learner/learner.h"

#include "tests/sanitizer.h"
#ifdef SRICS_TESTING_ASAN
#include <sanitizer/allocator_interface.h>
#endif

namespace srics::learner::testing {

// A learner's options for a test's run, its shape derived as a run's composition derives it.
inline LearnerOptions OptionsOf(const config::Config& config) {
  return LearnerOptionsFor(config, rl::RunShapeFor(config));
}

inline rl::Episode MakeEpisode(int num_entities, int num_steps, uint64_t seed, int subgoal_entity = 1,
                               int num_kinds = 0) {
  rl::Episode e;
  e.layout = {num_entities, num_kinds ? num_kinds : num_entities, false};
  e.num_steps = num_steps;
  e.action_dim = 2;
  for (int i = 0; i < num_entities; ++i) e.entity_kinds.push_back(static_cast<uint16_t>(i));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-0.02f, 0.02f);
  std::vector<float> xy(2 * num_entities);
  for (int i = 0; i < num_entities; ++i) {
    xy[2 * i] = -0.2f + 0.1f * i;
    xy[2 * i + 1] = 0.5f;
  }
  const int d = e.layout.entity_dim();
  for (int t = 0; t <= num_steps; ++t) {
    for (int i = 0; i < num_entities; ++i) {
      std::vector<float> token(d, 0.0f);
      token[e.entity_kinds[i]] = 1.0f;
      token[e.layout.num_kinds] = xy[2 * i];
      token[e.layout.num_kinds + 1] = xy[2 * i + 1];
      e.states.insert(e.states.end(), token.begin(), token.end());
    }
    if (t == num_steps) break;
    e.actions.push_back(u(rng) * 50);
    e.actions.push_back(u(rng) * 50);
    for (auto& v : xy) v += u(rng);
  }
  e.subgoal_entity = subgoal_entity;
  if (subgoal_entity >= 0) e.goal = {0.05f, 0.6f};
  e.mode = subgoal_entity >= 0 ? rl::EpisodeMode::kTrain : rl::EpisodeMode::kExplore;
  e.episode_id = seed;
  return e;
}

// Rearrange 2 sizes (arm + 2 pucks: K = 3, D = 5) with small networks and batches.
inline config::Config SmallRun(config::Method method) {
  config::Config c;
  c.env.num_pucks = 2;
  c.run.method = method;
  c.agent.network.embed_dim = 16;
  c.agent.network.heads = 2;
  c.agent.network.policy_hidden = {16};
  c.agent.network.q_hidden = {16};
  c.agent.sac.batch_size = 16;
  c.learner.warmup_steps = 100;
  c.learner.updates_per_step = 0.5;
  c.learner.rate_error_buffer = 4;
  return c;
}

// The resident set size of this process in kB (-1 when /proc does not tell).
inline long ResidentKb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

// The memory the process uses for its data: the resident size, or under AddressSanitizer
// (./tests/sanitize.sh), whose redzones and quarantine of freed blocks inflate the resident
// size several times over, the bytes of the live heap blocks as its allocator counts them.
inline long MemoryInUseKb() {
#ifdef SRICS_TESTING_ASAN
  return static_cast<long>(__sanitizer_get_current_allocated_bytes() / 1024);
#else
  return ResidentKb();
#endif
}

}  // namespace srics::learner::testing
