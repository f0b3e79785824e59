#include "common/rl/episode.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace srics::rl {
namespace {

std::string Str(double v) { return std::to_string(v); }

// "" when lo <= value <= hi, else "`field` <value> outside [lo, hi]".
std::string OutOfRange(const char* field, long long value, long long lo, long long hi) {
  if (value >= lo && value <= hi) return "";
  return std::string(field) + " " + std::to_string(value) + " outside [" + std::to_string(lo) + ", " +
         std::to_string(hi) + "]";
}

std::string SizeMismatch(const char* field, size_t got, size_t expected, const char* layout) {
  return std::string(field) + " has " + std::to_string(got) + " values, expected " + std::to_string(expected) + " (" +
         layout + ")";
}

// "" when every value is finite and |value| <= bound, else names the first offender.
// `field` and `index` say where it sits ("states[3]: entity 1 x").
template <typename Where>
std::string CheckBounded(float value, float bound, Where where) {
  if (std::isfinite(value) && std::fabs(value) <= bound) return "";
  return where() + " = " + Str(value) +
         (std::isfinite(value) ? " outside [-" + Str(bound) + ", " + Str(bound) + "]" : " is not finite");
}

// The fast checks below answer only "all good?" in one branch-free pass over the values (the
// compiler vectorizes them); when one says no, the detailed check that follows it names the
// offender. They accept exactly what the detailed checks accept: |v - center| <= tolerance is
// false for NaN and, with the tolerance capped at FLT_MAX, for infinities; with tolerance 0 it
// is v == center.
constexpr size_t kBlock = 4096;  // values per early-exit test

float Tolerance(float bound) { return std::min(bound, std::numeric_limits<float>::max()); }

// Nonzero when some |v[i] - center[i]| is not <= tolerance[i] (center and tolerance null: 0
// and `bound`). Blocks of 8 with a fixed inner count, which GCC vectorizes at -O2 too.
template <bool kPattern>
int Outside(const float* v, size_t n, const float* center, const float* tolerance, float bound) {
  auto outside = [&](size_t i) {
    if constexpr (kPattern)
      return static_cast<int>(!(std::fabs(v[i] - center[i]) <= tolerance[i]));
    else
      return static_cast<int>(!(std::fabs(v[i]) <= bound));
  };
  int lanes[8] = {};  // one accumulator per lane: no horizontal step inside the loop
  size_t i = 0;
  for (; i + 8 <= n; i += 8)
    for (size_t k = 0; k < 8; ++k) lanes[k] |= outside(i + k);
  int bad = 0;
  for (int lane : lanes) bad |= lane;
  for (; i < n; ++i) bad |= outside(i);
  return bad;
}

// Every state token against a pattern of the states (N x D, repeated for several steps): the
// one-hot columns equal their identifier (tolerance 0), positions and velocities within their
// bounds (center 0). The pattern is kept per thread and rebuilt only when the entity kinds,
// layout or bounds change (an actor's episodes share them). Sizes were checked (CheckSizes).
bool StatesLookRight(const Episode& e, const EpisodeLimits& limits) {
  struct Pattern {
    std::vector<uint16_t> kinds;
    int num_kinds = -1;
    bool velocities = false;
    float position = 0, velocity = 0;
    std::vector<float> center, tolerance;  // `steps` states
    size_t steps = 0;
  };
  thread_local Pattern p;
  const EntityLayout& l = e.layout;
  const size_t d = static_cast<size_t>(l.entity_dim()), s = static_cast<size_t>(l.state_size());
  const float position = Tolerance(limits.max_abs_position), velocity = Tolerance(limits.max_abs_velocity);
  // bit-exact comparison of the bounds (a NaN bound never matches: rebuilt each time)
  if (p.kinds != e.entity_kinds || p.num_kinds != l.num_kinds || p.velocities != l.velocities ||
      !(p.position == position) || !(p.velocity == velocity)) {
    p.kinds = e.entity_kinds;
    p.num_kinds = l.num_kinds;
    p.velocities = l.velocities;
    p.position = position;
    p.velocity = velocity;
    p.steps = std::max<size_t>(1, 512 / s);  // a few hundred values per pass
    p.center.assign(s, 0.0f);
    p.tolerance.resize(s);
    for (size_t entity = 0; entity < static_cast<size_t>(l.num_entities); ++entity) {
      for (size_t column = 0; column < d; ++column) {
        const int col = static_cast<int>(column);
        const size_t i = entity * d + column;
        if (col < l.num_kinds) {
          p.center[i] = col == e.entity_kinds[entity] ? 1.0f : 0.0f;
          p.tolerance[i] = 0.0f;
        } else {
          p.tolerance[i] = col < l.num_kinds + 2 ? position : velocity;
        }
      }
    }
    p.center.resize(p.steps * s);
    p.tolerance.resize(p.steps * s);
    for (size_t step = 1; step < p.steps; ++step) {
      std::copy_n(p.center.begin(), s, p.center.begin() + step * s);
      std::copy_n(p.tolerance.begin(), s, p.tolerance.begin() + step * s);
    }
  }
  const size_t n = e.states.size(), chunk = p.steps * s;
  for (size_t start = 0; start < n; start += chunk)
    if (Outside<true>(e.states.data() + start, std::min(chunk, n - start), p.center.data(), p.tolerance.data(), 0.0f))
      return false;
  return true;
}

std::string CheckLayout(const Episode& e, const EpisodeLimits& limits) {
  const EntityLayout& l = e.layout;
  // the run's limits, never wider than the contract's
  if (auto r = OutOfRange("num_entities", l.num_entities, std::max(1, limits.min_entities),
                          std::min(kMaxEntities, limits.max_entities));
      !r.empty())
    return r;
  if (limits.num_kinds > 0 && l.num_kinds != limits.num_kinds)
    return "num_kinds " + std::to_string(l.num_kinds) + ", this run has " + std::to_string(limits.num_kinds) +
           " (entity_dim " + std::to_string(l.entity_dim()) + ")";
  if (auto r = OutOfRange("num_kinds", l.num_kinds, 1, kMaxEntities); !r.empty()) return r;
  if (l.velocities != limits.velocities)
    return std::string("velocities ") + (l.velocities ? "present" : "absent") + ", this run has them " +
           (limits.velocities ? "present" : "absent");
  if (limits.action_dim > 0 && e.action_dim != limits.action_dim)
    return "action_dim " + std::to_string(e.action_dim) + ", this run has " + std::to_string(limits.action_dim);
  if (auto r = OutOfRange("action_dim", e.action_dim, 1, kMaxActionDim); !r.empty()) return r;
  if (auto r = OutOfRange("num_steps", e.num_steps, 1, std::min(kMaxEpisodeSteps, limits.max_steps)); !r.empty())
    return r;
  if (auto r = OutOfRange("mode", static_cast<int>(e.mode), 0, 2); !r.empty()) return r;
  return "";
}

std::string CheckSizes(const Episode& e) {
  const EntityLayout& l = e.layout;
  const size_t n = static_cast<size_t>(l.num_entities);
  if (e.entity_kinds.size() != n) return SizeMismatch("entity_kinds", e.entity_kinds.size(), n, "N");
  for (size_t i = 0; i < n; ++i)
    if (e.entity_kinds[i] >= l.num_kinds)
      return "entity_kinds[" + std::to_string(i) + "] = " + std::to_string(e.entity_kinds[i]) +
             " not below num_kinds " + std::to_string(l.num_kinds);
  const size_t states = static_cast<size_t>(e.num_steps + 1) * l.state_size();
  if (e.states.size() != states) return SizeMismatch("states", e.states.size(), states, "(T+1) x N x D");
  const size_t actions = static_cast<size_t>(e.num_steps) * e.action_dim;
  if (e.actions.size() != actions) return SizeMismatch("actions", e.actions.size(), actions, "T x A");
  if (e.subgoal_entity < -1 || e.subgoal_entity >= l.num_entities)
    return "subgoal_entity " + std::to_string(e.subgoal_entity) + " outside [-1, N)";
  // a tied pair attempted as one (graph.object_ties: joint): its second object's xy after the first's
  if (e.subgoal_entity >= 0 && e.goal.size() != 2 && e.goal.size() != 4)
    return SizeMismatch("goal", e.goal.size(), 2, "xy of the subgoal entity (4: and of its tied partner)");
  if (e.subgoal_entity < 0 && !e.goal.empty() && e.goal.size() != 2 * n)
    return SizeMismatch("goal", e.goal.size(), 2 * n, "2N for a full goal, or none");
  if (e.mode != EpisodeMode::kExplore && e.goal.empty()) return "goal missing from a train or eval episode";
  if (n < 64 && (e.ancestor_mask >> n) != 0) return "ancestor_mask names entities at or above N";
  return "";
}

// Every state token: the one-hot of its entity's kind, then bounded positions and velocities.
std::string CheckStates(const Episode& e, const EpisodeLimits& limits) {
  const EntityLayout& l = e.layout;
  const int d = l.entity_dim();
  for (size_t i = 0; i < e.states.size(); ++i) {
    const int column = static_cast<int>(i % d);
    const int entity = static_cast<int>(i / d) % l.num_entities;
    const float v = e.states[i];
    auto where = [&] {
      return "states[" + std::to_string(i) + "] (step " + std::to_string(i / l.state_size()) + ", entity " +
             std::to_string(entity) + ", column " + std::to_string(column) + ")";
    };
    if (column < l.num_kinds) {
      const float want = column == e.entity_kinds[entity] ? 1.0f : 0.0f;
      if (v != want)
        return where() + " = " + Str(v) + ": the identifier one-hot of kind " + std::to_string(e.entity_kinds[entity]) +
               " needs " + Str(want);
    } else {
      const float bound = column < l.num_kinds + 2 ? limits.max_abs_position : limits.max_abs_velocity;
      if (auto r = CheckBounded(v, bound, where); !r.empty()) return r;
    }
  }
  return "";
}

std::string CheckValues(const std::vector<float>& values, const char* field, float bound) {
  for (size_t i = 0; i < values.size(); ++i)
    if (auto r = CheckBounded(values[i], bound, [&] { return std::string(field) + "[" + std::to_string(i) + "]"; });
        !r.empty())
      return r;
  return "";
}

// HAC's subgoal record: where each subgoal starts, its xy per entity and its test flag.
std::string CheckSubgoals(const Episode& e, const EpisodeLimits& limits) {
  const size_t k = e.subgoal_starts.size();
  if (k == 0) {
    if (!e.subgoals.empty() || !e.subgoal_tests.empty()) return "subgoals or subgoal_tests without subgoal_starts";
    return "";
  }
  if (limits.max_subgoal_steps == kNoSubgoals) return "subgoal_starts present: this run's episodes carry no subgoals";
  if (e.mode != EpisodeMode::kTrain) return "subgoal_starts in a non-training episode";
  if (e.subgoal_starts[0] != 0) return "subgoal_starts[0] = " + std::to_string(e.subgoal_starts[0]) + ", must be 0";
  for (size_t i = 0; i < k; ++i) {
    const int start = e.subgoal_starts[i];
    const int end = i + 1 < k ? e.subgoal_starts[i + 1] : e.num_steps;
    if (end <= start)
      return "subgoal_starts[" + std::to_string(i) + "] = " + std::to_string(start) +
             (i + 1 < k ? ": not below the next start " : ": not below num_steps ") + std::to_string(end);
    if (limits.max_subgoal_steps > 0 && end - start > limits.max_subgoal_steps)
      return "subgoal " + std::to_string(i) + " held " + std::to_string(end - start) + " steps, this run allows " +
             std::to_string(limits.max_subgoal_steps);
  }
  const size_t values = k * 2 * static_cast<size_t>(e.layout.num_entities);
  if (e.subgoals.size() != values) return SizeMismatch("subgoals", e.subgoals.size(), values, "K x 2N");
  if (e.subgoal_tests.size() != k) return SizeMismatch("subgoal_tests", e.subgoal_tests.size(), k, "K");
  for (size_t i = 0; i < k; ++i)
    if (e.subgoal_tests[i] > 1)
      return "subgoal_tests[" + std::to_string(i) + "] = " + std::to_string(e.subgoal_tests[i]) + ", must be 0 or 1";
  if (AllFiniteWithin(e.subgoals.data(), e.subgoals.size(), limits.max_abs_position)) return "";
  return CheckValues(e.subgoals, "subgoals", limits.max_abs_position);
}

}  // namespace

bool AllFiniteWithin(const float* values, size_t n, float bound) {
  const float tolerance = Tolerance(bound);
  for (size_t start = 0; start < n; start += kBlock)
    if (Outside<false>(values + start, std::min(kBlock, n - start), nullptr, nullptr, tolerance)) return false;
  return true;
}

EpisodeLimits LimitsOfLayout(const EntityLayout& layout, int action_dim) {
  EpisodeLimits limits;
  limits.min_entities = limits.max_entities = layout.num_entities;
  limits.num_kinds = layout.num_kinds;
  limits.velocities = layout.velocities;
  limits.action_dim = action_dim;
  return limits;
}

std::string ValidateEpisode(const Episode& e, const EpisodeLimits& limits) {
  if (auto r = CheckLayout(e, limits); !r.empty()) return r;
  if (auto r = CheckSizes(e); !r.empty()) return r;
  // the detailed value checks run only when a fast one found something (to name it)
  if (!StatesLookRight(e, limits))
    if (auto r = CheckStates(e, limits); !r.empty()) return r;
  if (!AllFiniteWithin(e.actions.data(), e.actions.size(), limits.max_abs_action))
    if (auto r = CheckValues(e.actions, "actions", limits.max_abs_action); !r.empty()) return r;
  if (!AllFiniteWithin(e.goal.data(), e.goal.size(), limits.max_abs_position))
    if (auto r = CheckValues(e.goal, "goal", limits.max_abs_position); !r.empty()) return r;
  return CheckSubgoals(e, limits);
}

}  // namespace srics::rl
