#include "deploy/monitor/monitor_state.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace srics::monitor {

const char* NodeHealthName(NodeHealth health) {
  switch (health) {
    case NodeHealth::kAlive: return "alive";
    case NodeHealth::kQuiet: return "quiet";
    case NodeHealth::kExited: return "exited";
    case NodeHealth::kLost: return "LOST";
  }
  return "invalid";
}

std::chrono::milliseconds LostAfter(const config::TransportConfig& transport) {
  const double seconds = transport.liveliness_lease_s + 2.0 * transport.status_period_s;
  return std::chrono::milliseconds(static_cast<int64_t>(std::ceil(seconds * 1000.0)));
}

std::string PrintableText(std::string_view text) {
  std::string out(text);
  for (char& c : out)
    if (c < 0x20 || c > 0x7e) c = '?';  // char is signed here: bytes >= 0x80 are negative
  return out;
}

namespace {

// Of the entries `evictable` admits, the one heard from least: one sample before many (a
// flood's invented ids are heard from once; a real node every status period), then the
// longest silent. end() when none is admitted.
template <typename Map, typename Count, typename LastHeard, typename Evictable>
typename Map::iterator LeastHeard(Map& map, Count count, LastHeard last_heard, Evictable evictable) {
  auto victim = map.end();
  for (auto it = map.begin(); it != map.end(); ++it) {
    if (!evictable(it)) continue;
    if (victim == map.end()) {
      victim = it;
      continue;
    }
    const bool once = count(it->second) <= 1, victim_once = count(victim->second) <= 1;
    if (once != victim_once ? once : last_heard(it->second) < last_heard(victim->second)) victim = it;
  }
  return victim;
}

}  // namespace

RunView& RunOf(MonitorState* state, const std::string& printable_run_id, Clock::time_point now) {
  // Not a structured binding: clang (the sanitizer build) cannot capture one in a lambda.
  const auto emplaced = state->runs.try_emplace(printable_run_id);
  const auto it = emplaced.first;
  if (emplaced.second && state->runs.size() > std::max<size_t>(state->max_runs, 1)) {
    const auto victim = LeastHeard(
        state->runs, [](const RunView& r) { return r.samples; }, [](const RunView& r) { return r.last_sample; },
        [&](auto candidate) { return candidate != it && candidate->first != state->own_run_id; });
    if (victim != state->runs.end()) {
      state->runs.erase(victim);
      ++state->evicted_runs;
    }
  }
  it->second.last_sample = now;
  ++it->second.samples;
  return it->second;
}

void Apply(MonitorState* state, const std::string& run_id, const rl::NodeStatus& received, Clock::time_point now) {
  rl::NodeStatus status = received;
  for (std::string* text : {&status.role, &status.host, &status.report.detail}) *text = PrintableText(*text);
  NodeKey key{PrintableText(run_id), status.role, status.node_id};
  const auto emplaced = state->nodes.try_emplace(std::move(key));
  const auto it = emplaced.first;
  const bool inserted = emplaced.second;
  if (inserted && state->nodes.size() > std::max<size_t>(state->max_nodes, 1)) {
    const auto victim = LeastHeard(
        state->nodes, [](const NodeEntry& n) { return n.statuses; }, [](const NodeEntry& n) { return n.last_seen; },
        [&](auto candidate) { return candidate != it; });
    if (victim != state->nodes.end()) {
      state->nodes.erase(victim);
      ++state->evicted_nodes;
    }
  }
  NodeEntry& node = it->second;
  if (inserted) node.first_seen = now;
  node.status = std::move(status);
  node.last_seen = now;
  ++node.statuses;
}

void Apply(MonitorState* state, const std::string& run_id, const rl::LearnerReport& stats, Clock::time_point now) {
  RunView& run = RunOf(state, PrintableText(run_id), now);
  run.learner = stats;
  run.learner_received = now;
  const uint64_t steps = stats.training_env_steps;
  if (!run.step_history.empty() && steps < run.step_history.back().second) {
    run.step_history.clear();
    run.learner_history = LearnerHistory{.max_points = run.learner_history.max_points};
  }
  Add(&run.learner_history, {.updates = stats.updates,
                             .env_steps = steps,
                             .q_loss = static_cast<float>(stats.q_loss),
                             .policy_loss = static_cast<float>(stats.policy_loss),
                             .alpha = static_cast<float>(stats.alpha),
                             .entropy = static_cast<float>(stats.entropy),
                             .mean_reward = static_cast<float>(stats.mean_reward),
                             .updates_per_second = static_cast<float>(stats.updates_per_second),
                             .inserts_per_second = static_cast<float>(stats.inserts_per_second)});
  run.step_history.emplace_back(now, steps);
  while (run.step_history.size() > 2 && now - run.step_history.front().first > kRateWindow)
    run.step_history.pop_front();
}

void Add(LearnerHistory* history, const LearnerPoint& point) {
  history->latest = point;
  if (history->seen++ % history->stride != 0) return;
  history->points.push_back(point);
  if (history->points.size() <= std::max<size_t>(history->max_points, 2)) return;
  // keep points 0, 2, 4, ...: the stride doubles, so the kept ones stay evenly spaced
  size_t kept = 0;
  for (size_t i = 0; i < history->points.size(); i += 2) history->points[kept++] = history->points[i];
  history->points.resize(kept);
  history->stride *= 2;
}

std::optional<double> EnvStepRate(const RunView& run) {
  if (run.step_history.size() < 2) return std::nullopt;
  const auto& [t0, s0] = run.step_history.front();
  const auto& [t1, s1] = run.step_history.back();
  const double seconds = std::chrono::duration<double>(t1 - t0).count();
  if (seconds < 5) return std::nullopt;
  return static_cast<double>(s1 - s0) / seconds;
}

void Apply(MonitorState* state, const std::string& run_id, const rl::EvalReport& result, Clock::time_point now) {
  RunView& run = RunOf(state, PrintableText(run_id), now);
  if (result.policy_version == 0) {
    // the passive policy is evaluated once per evaluating actor; the first one is the baseline
    if (!run.passive) run.passive = result;
    return;
  }
  run.evals.push_back(result);
  if (run.evals.size() > state->max_evals_kept)
    run.evals.erase(run.evals.begin(),
                    run.evals.begin() + static_cast<ptrdiff_t>(run.evals.size() - state->max_evals_kept));
}

void Apply(MonitorState* state, const std::string& run_id, const rl::GraphUpdate& graph, Clock::time_point now) {
  RunView& run = RunOf(state, PrintableText(run_id), now);
  run.graph = graph;
  run.graph_received = now;
}

void Apply(MonitorState* state, const std::string& run_id, const rl::WeightsUpdate& weights, Clock::time_point now) {
  RunView& run = RunOf(state, PrintableText(run_id), now);
  WeightsInfo info;
  info.version = weights.version;
  info.update_count = weights.update_count;
  info.architecture = PrintableText(weights.architecture);
  info.num_parameters = weights.parameters.size();
  info.received = now;
  run.weights = std::move(info);
}

std::string PassiveMismatch(const rl::EvalReport& report, const rl::EvaluationSummary& expected) {
  const rl::EvaluationSummary& result = report.summary;
  // episodes as the wire counts them (unsigned)
  if (static_cast<uint32_t>(result.episodes) != static_cast<uint32_t>(expected.episodes))
    return std::to_string(static_cast<uint32_t>(result.episodes)) + " episodes, the run's passive evaluation has " +
           std::to_string(expected.episodes);
  auto differs = [](double got, double want) {
    return !std::isfinite(got) || std::fabs(got - want) > kPassiveTolerance * std::max(1.0, std::fabs(want));
  };
  char text[160];
  auto describe = [&](const char* what, double got, double want) {
    std::snprintf(text, sizeof text, "%s %.4f, the run's passive evaluation gives %.4f", what, got, want);
    return std::string(text);
  };
  if (differs(result.avg_object_distance, expected.avg_object_distance))
    return describe("avg object distance", result.avg_object_distance, expected.avg_object_distance);
  if (differs(result.avg_distance, expected.avg_distance))
    return describe("avg distance", result.avg_distance, expected.avg_distance);
  if (differs(result.success_rate, expected.success_rate))
    return describe("success rate", result.success_rate, expected.success_rate);
  if (result.entity_distance.size() != expected.entity_distance.size())
    return std::to_string(result.entity_distance.size()) + " entity distances, the run has " +
           std::to_string(expected.entity_distance.size());
  for (size_t i = 0; i < result.entity_distance.size(); ++i)
    if (differs(result.entity_distance[i], expected.entity_distance[i]))
      return describe(("entity " + std::to_string(i) + " distance").c_str(), result.entity_distance[i],
                      expected.entity_distance[i]);
  return "";
}

NodeHealth HealthOf(const MonitorState& state, const NodeEntry& node, Clock::time_point now) {
  if (now - node.last_seen <= state.lost_after) return NodeHealth::kAlive;
  if (node.status.report.phase == rl::NodePhase::kStopping) return NodeHealth::kExited;
  if (state.liveliness_known) {
    size_t expected = 0;  // nodes whose writer should still be there
    for (const auto& [key, other] : state.nodes) expected += other.status.report.phase != rl::NodePhase::kStopping;
    if (state.status_writers_alive >= expected) return NodeHealth::kQuiet;
  }
  return NodeHealth::kLost;
}

std::vector<NodeKey> NewlyGone(const MonitorState& state, Clock::time_point now,
                               std::map<NodeKey, NodeHealth>* known_gone) {
  std::vector<NodeKey> gone;
  for (const auto& [key, node] : state.nodes) {
    const NodeHealth health = HealthOf(state, node, now);
    auto it = known_gone->find(key);
    if (health == NodeHealth::kAlive || health == NodeHealth::kQuiet) {
      if (it != known_gone->end()) known_gone->erase(it);
    } else if (it == known_gone->end() || it->second != health) {
      (*known_gone)[key] = health;
      gone.push_back(key);
    }
  }
  return gone;
}

uint64_t BudgetEnvSteps(const RunView& run) { return run.learner ? run.learner->budget_env_steps : 0; }

uint64_t EnvSteps(const RunView& run) {
  uint64_t steps = run.learner ? run.learner->training_env_steps : 0;
  if (!run.evals.empty()) steps = std::max(steps, run.evals.back().env_steps);
  return steps;
}

const rl::EvalReport* LatestEval(const RunView& run) { return run.evals.empty() ? nullptr : &run.evals.back(); }

size_t EdgeCount(const rl::GraphUpdate& update) {
  const rl::InteractionGraph& graph = update.graph;
  const size_t n = static_cast<size_t>(graph.num_entities);
  size_t edges = 0;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j)
      if (i != j && i * n + j < graph.adjacency.size() && graph.adjacency[i * n + j]) ++edges;
  return edges;
}

}  // namespace srics::monitor
