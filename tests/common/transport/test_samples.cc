#include "tests/common/transport/test_samples.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "common/rl/graph.h"
#include "common/transport/validation.h"
#include "common/transport/wire.h"

namespace srics::transport::testing {
namespace {

// A value in [-1, 1) that depends on seed and index (splitmix-style hash).
float Value(uint64_t seed, uint64_t i) {
  uint64_t z = seed * 0x9E3779B97F4A7C15ull + i + 1;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<float>(static_cast<double>(z >> 11) / 4503599627370496.0 - 1.0);
}

}  // namespace

int ReserveDomain(int first, int count) {
  static std::mutex mutex;
  // by process: a forked child shares its parent's lock, so it reserves a domain of its own
  static std::map<std::tuple<pid_t, int, int>, int> reserved;  // the lock files stay open
  std::lock_guard<std::mutex> lock(mutex);
  const std::tuple<pid_t, int, int> key{getpid(), first, count};
  if (const auto it = reserved.find(key); it != reserved.end()) return it->second;
  const int start = static_cast<int>(getpid() % count);
  for (int k = 0; k < count; ++k) {
    const int domain = first + (start + k) % count;
    const std::string path = "/tmp/srics-test-domain-" + std::to_string(domain) + ".lock";
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {  // released by the kernel when this process ends
      reserved[key] = domain;
      return domain;
    }
    ::close(fd);
  }
  throw std::runtime_error("every test domain in " + std::to_string(first) + ".." + std::to_string(first + count - 1) +
                           " is held by another process");
}

config::TransportConfig IsolatedTransportConfig(const std::string& prefix) {
  config::TransportConfig config;
  // domains 20..219 keep every RTPS port below 65536 with 64 participants per host
  config.domain_id = ReserveDomain(20, 200);
  config.run_id = prefix + "-" + std::to_string(getpid());
  return config;
}

rl::Episode MakeEpisode(uint64_t seed, int steps, int entities) {
  rl::Episode e;
  e.layout = {entities, kSampleKinds, false};
  e.actor_id = static_cast<uint32_t>(seed % 7 + 1);
  e.episode_id = seed;
  e.mode = rl::EpisodeMode::kTrain;
  e.policy_version = 1000 + seed;
  e.graph_version = 3;
  e.action_dim = 3;
  e.num_steps = steps;
  for (int i = 0; i < entities; ++i) e.entity_kinds.push_back(static_cast<uint16_t>((i + seed) % kSampleKinds));
  const int d = e.layout.entity_dim();
  e.states.resize(static_cast<size_t>(steps + 1) * entities * d);
  for (size_t i = 0; i < e.states.size(); ++i) {
    const int column = static_cast<int>(i % d), entity = static_cast<int>(i / d) % entities;
    e.states[i] = column < kSampleKinds ? (column == e.entity_kinds[entity] ? 1.0f : 0.0f)  // identifier
                                        : 0.5f * Value(seed, i);                            // xy in m
  }
  e.actions.resize(static_cast<size_t>(steps) * e.action_dim);
  for (size_t i = 0; i < e.actions.size(); ++i) e.actions[i] = Value(seed + 1, i);
  e.subgoal_entity = static_cast<int>(seed % entities);
  e.goal = {Value(seed, 99), Value(seed, 100)};
  e.ancestor_mask = (1ull << e.subgoal_entity) | 1ull;
  // HAC's subgoal record (contract 2): subgoals from steps 0 and T / 2, the second a test
  e.subgoal_starts = {0};
  if (steps >= 2) e.subgoal_starts.push_back(static_cast<uint16_t>(steps / 2));
  for (size_t k = 0; k < e.subgoal_starts.size(); ++k) {
    for (int j = 0; j < 2 * entities; ++j) e.subgoals.push_back(0.5f * Value(seed + 2 + k, j));
    e.subgoal_tests.push_back(static_cast<uint8_t>(k % 2));
  }
  return e;
}

rl::EpisodeLimits SampleEpisodeLimits() {
  rl::EpisodeLimits limits;
  limits.max_entities = kSampleKinds;
  limits.num_kinds = kSampleKinds;
  limits.velocities = false;
  limits.action_dim = 3;
  return limits;
}

ReaderOptions SampleEpisodeReader(const std::string& topic_name) {
  ReaderOptions options;
  options.topic_name = topic_name;
  options.episode_limits = SampleEpisodeLimits();
  return options;
}

rl::WeightsUpdate MakePolicyWeights(uint64_t seed, size_t count) {
  rl::WeightsUpdate w;
  w.version = seed + 1;
  w.update_count = 500 * (seed + 1);
  w.architecture = "attention-sac/v1 entities=5 dim=6 hidden=256x3 seed=" + std::to_string(seed);
  w.parameters.resize(count);
  for (size_t i = 0; i < count; ++i) w.parameters[i] = Value(seed, i) * 3;
  // values whose bits a lossy path would change
  if (count > 4) {
    w.parameters[0] = -0.0f;
    w.parameters[1] = std::numeric_limits<float>::denorm_min();
    w.parameters[2] = rl::kMaxAbsParameter;  // the largest magnitudes the contract allows
    w.parameters[3] = -rl::kMaxAbsParameter;
  }
  return w;
}

rl::GraphUpdate MakeInteractionGraph(uint64_t seed) {
  rl::GraphUpdate g;
  const int n = 5;
  g.version = seed + 1;
  g.graph.num_entities = n;
  g.threshold = 0.25f;
  for (int i = 0; i < n * n; ++i) {
    g.mean_weights.push_back(std::fabs(Value(seed, i)));
    g.graph.adjacency.push_back(g.mean_weights.back() > g.threshold ? 1 : 0);
  }
  g.graph.action_entity = 0;
  for (int i = 0; i < n; ++i) {
    g.structure.ancestor_mask.push_back((1ull << i) - 1);
    g.structure.depth.push_back(i == n - 1 ? -1 : i);
  }
  g.held_out_loss = 0.0123f + static_cast<float>(seed);
  g.training_updates = 20000 + seed;
  g.episodes_used = 1234;
  return g;
}

rl::EvalReport MakeEvalResult(uint64_t seed) {
  rl::EvalReport e;
  e.actor_id = 2;
  e.policy_version = 40 + seed;
  e.graph_version = 2;
  e.env_steps = 123456789ull + seed;
  rl::EvaluationSummary& r = e.summary;
  r.episodes = 50;
  r.avg_distance = 0.125f;
  r.avg_object_distance = 0.0625f;
  r.success_rate = 0.75f;
  for (int i = 0; i < 5; ++i) {
    r.entity_distance.push_back(std::fabs(Value(seed, i)));
    r.subgoal_success.push_back((Value(seed, i + 10) + 1) / 2);
  }
  r.selectivity = 0.5f;
  r.selectivity_episodes = r.episodes;                     // as received: every episode counts
  r.independent_solved = 5 + static_cast<uint32_t>(seed);  // non-zero: the transport tests see them cross
  r.independent_undone = 2;
  return e;
}

rl::LearnerReport MakeLearnerStats(uint64_t seed) {
  rl::LearnerReport s;
  s.updates = 1000 + seed;
  s.transitions_inserted = 20000 + seed;
  s.training_env_steps = 15000 + seed;
  s.budget_env_steps = 600000;
  s.replay_size = 19000 + seed;
  s.episodes_accepted = 1000;
  s.episodes_rejected = 3;
  s.policy_version = 10;
  s.q_loss = 0.5f;
  s.policy_loss = -1.25f;
  s.alpha = 0.01f;
  s.entropy = -2.0f;
  s.updates_per_second = 250.5f;
  s.inserts_per_second = 1000.25f;
  s.mean_reward = -0.375f;
  return s;
}

rl::NodeStatus MakeNodeStatus(uint64_t seed) {
  rl::NodeStatus s;
  s.role = "actor";
  s.node_id = static_cast<uint32_t>(seed);
  s.host = "host-" + std::to_string(seed);
  s.pid = 4242;
  s.uptime_ms = 3600000;
  s.report.phase = rl::NodePhase::kTraining;
  s.report.policy_version = 7;
  s.report.graph_version = 1;
  s.report.steps = 99999;
  s.report.dropped = 2;
  s.report.detail = "episode 12 of subgoal 3";
  return s;
}

rl::GraphUpdate MakeCompleteGraph(int entities, uint64_t version) {
  rl::GraphUpdate g;
  g.version = version;
  g.graph.num_entities = entities;
  g.graph.adjacency.assign(static_cast<size_t>(entities) * entities, 1);
  g.structure = rl::ComputeSubgoalStructure(g.graph);
  g.mean_weights.assign(static_cast<size_t>(entities) * entities, 0.9);
  g.threshold = 0.5;
  return g;
}

}  // namespace srics::transport::testing
