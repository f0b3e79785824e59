#pragma once
// A tiny hand-written 2-D physics for the graph service's tests (no MuJoCo): an arm moved by
// the action, pucks pushed out of the arm's way, static pucks that never move, and ropes
// that keep two pucks within a length. Its true interaction graph is known, so learning can
// be checked against it quickly.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <random>
#include <utility>
#include <vector>

#include "common/rl/episode.h"
#include "graph_service/service.h"

namespace srics::graph_service::testing {

struct ToyWorldConfig {
  int num_pucks = 2;
  std::vector<int> static_pucks;           // entity numbers (1..n) that never move
  std::vector<std::pair<int, int>> ropes;  // pairs kept within rope_length
  double rope_length = 0.13;
  double puck_radius = 0.04;
  double arm_radius = 0.03;
  double action_scale = 0.1;
  // a free puck keeps this fraction of its last step's displacement (0: pucks stop at once)
  double slide = 0;
  int steps = 50;
};

class ToyWorld {
 public:
  explicit ToyWorld(ToyWorldConfig config) : c_(std::move(config)) {}

  int num_entities() const { return c_.num_pucks + 1; }

  // A training episode (mode kTrain) as a policy kicking puck `pushed` away from puck `other`
  // would make: the two start `gap` apart in a random direction around the table's middle, the
  // arm just behind `pushed`; the arm drives (with some noise) away from `other` for
  // `push_steps` steps, then backs off. With `slide`, the puck slides on, and a rope between
  // the two goes taut and drags `other` while the arm is away: what random actions rarely do.
  // Other pucks start where RandomEpisode puts them.
  rl::Episode PushEpisode(uint64_t seed, int pushed, int other, double gap, int push_steps) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> angle(0, 2 * 3.14159265358979), noise(-0.3, 0.3);
    rl::Episode ep = RandomEpisode(seed);  // the other pucks' start
    const double a = angle(rng), ux = std::cos(a), uy = std::sin(a);
    const std::array<double, 2> middle = {0.0, 0.57};
    pos_.resize(num_entities());
    velocity_.assign(num_entities(), {0.0, 0.0});
    pos_[other] = {middle[0] - ux * gap / 2, middle[1] - uy * gap / 2};
    pos_[pushed] = {middle[0] + ux * gap / 2, middle[1] + uy * gap / 2};
    const double behind = c_.arm_radius + c_.puck_radius + 0.002;
    pos_[0] = {pos_[pushed][0] - ux * behind, pos_[pushed][1] - uy * behind};
    for (int i = 1; i < num_entities(); ++i) {
      if (i == pushed || i == other) continue;
      pos_[i] = {ep.layout.x(ep.state(0), i), ep.layout.y(ep.state(0), i)};
    }
    ep.mode = rl::EpisodeMode::kTrain;
    ep.subgoal_entity = pushed;  // where it ends up (the goal plays no part in the graph)
    ep.states.clear();
    ep.actions.clear();
    Record(&ep);
    for (int t = 0; t < c_.steps; ++t) {
      const double sign = t < push_steps ? 1.0 : -1.0;
      const double ax = std::clamp(sign * ux + noise(rng), -1.0, 1.0),
                   ay = std::clamp(sign * uy + noise(rng), -1.0, 1.0);
      ep.actions.push_back(static_cast<float>(ax));
      ep.actions.push_back(static_cast<float>(ay));
      Step(ax, ay);
      Record(&ep);
    }
    ep.goal = {static_cast<float>(pos_[pushed][0]), static_cast<float>(pos_[pushed][1])};
    return ep;
  }

  // One episode of uniformly random actions from `seed`.
  rl::Episode RandomEpisode(uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> ux(-0.2, 0.2), uy(0.45, 0.7), ua(-1, 1);
    const int n = num_entities();
    // rejection sampling of the initial positions, as in the real environment
    pos_.assign(n, {0.0, 0.4});
    velocity_.assign(n, {0.0, 0.0});
    for (int i = 1; i < n; ++i) {
      for (int attempt = 0; attempt < 10000; ++attempt) {
        pos_[i] = {ux(rng), uy(rng)};
        bool ok = Dist(pos_[i], pos_[0]) >= 0.06 + c_.puck_radius;
        for (int j = 1; j < i; ++j) ok = ok && Dist(pos_[i], pos_[j]) >= 0.10;
        for (auto [a, b] : c_.ropes)
          if ((a == i && b < i) || (b == i && a < i)) ok = ok && Dist(pos_[a], pos_[b]) <= c_.rope_length;
        if (ok) break;
      }
    }
    rl::Episode ep;
    ep.layout = {n, n, false};
    for (int i = 0; i < n; ++i) ep.entity_kinds.push_back(static_cast<uint16_t>(i));
    ep.num_steps = c_.steps;
    ep.action_dim = 2;
    ep.mode = rl::EpisodeMode::kExplore;
    ep.episode_id = seed;
    Record(&ep);
    for (int t = 0; t < c_.steps; ++t) {
      const double ax = ua(rng), ay = ua(rng);
      ep.actions.push_back(static_cast<float>(ax));
      ep.actions.push_back(static_cast<float>(ay));
      Step(ax, ay);
      Record(&ep);
    }
    return ep;
  }

 private:
  static double Dist(const std::array<double, 2>& a, const std::array<double, 2>& b) {
    return std::hypot(a[0] - b[0], a[1] - b[1]);
  }
  bool IsStatic(int i) const {
    return std::find(c_.static_pucks.begin(), c_.static_pucks.end(), i) != c_.static_pucks.end();
  }
  void Record(rl::Episode* ep) const {
    const int n = num_entities();
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < n; ++k) ep->states.push_back(k == i ? 1.f : 0.f);
      ep->states.push_back(static_cast<float>(pos_[i][0]));
      ep->states.push_back(static_cast<float>(pos_[i][1]));
    }
  }
  // moves `mover` (and, if free, the other) so that they are `gap` apart
  void Separate(int a, int b, double gap, bool a_moves) {
    double dx = pos_[b][0] - pos_[a][0], dy = pos_[b][1] - pos_[a][1];
    double d = std::hypot(dx, dy);
    if (d >= gap) return;
    if (d < 1e-9) {
      dx = 1;
      dy = 0;
      d = 1;
    }
    const double push = gap - d;
    const bool b_moves = !IsStatic(b);
    if (!b_moves && !a_moves) return;
    const double share_b = a_moves ? (b_moves ? 0.5 : 0.0) : 1.0;
    pos_[b][0] += dx / d * push * share_b;
    pos_[b][1] += dy / d * push * share_b;
    pos_[a][0] -= dx / d * push * (1 - share_b);
    pos_[a][1] -= dy / d * push * (1 - share_b);
  }
  void Step(double ax, double ay) {
    const std::vector<std::array<double, 2>> before = pos_;
    const int n = num_entities();
    const int substeps = 10;
    ax = std::clamp(ax, -1.0, 1.0);
    ay = std::clamp(ay, -1.0, 1.0);
    for (int s = 0; s < substeps; ++s) {
      for (int i = 1; i < n; ++i)
        if (!IsStatic(i))
          for (int a = 0; a < 2; ++a) pos_[i][a] += velocity_[i][a] / substeps;
      pos_[0][0] = std::clamp(pos_[0][0] + c_.action_scale * ax / substeps, -0.245, 0.245);
      pos_[0][1] = std::clamp(pos_[0][1] + c_.action_scale * ay / substeps, 0.40, 0.75);
      // the arm pushes pucks; it is never pushed back
      for (int i = 1; i < n; ++i)
        if (!IsStatic(i)) Separate(0, i, c_.arm_radius + c_.puck_radius, false);
      // pucks push each other, static ones do not give way
      for (int i = 1; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
          if (!IsStatic(i))
            Separate(i, j, 2 * c_.puck_radius, true);
          else
            Separate(i, j, 2 * c_.puck_radius, false);
      // ropes pull the pair together when stretched
      for (auto [a, b] : c_.ropes) {
        const double dx = pos_[b][0] - pos_[a][0], dy = pos_[b][1] - pos_[a][1];
        const double d = std::hypot(dx, dy);
        if (d <= c_.rope_length) continue;
        const double pull = (d - c_.rope_length) / 2;
        pos_[a][0] += dx / d * pull;
        pos_[a][1] += dy / d * pull;
        pos_[b][0] -= dx / d * pull;
        pos_[b][1] -= dy / d * pull;
      }
      for (int i = 1; i < n; ++i) {
        pos_[i][0] = std::clamp(pos_[i][0], -0.24, 0.24);
        pos_[i][1] = std::clamp(pos_[i][1], 0.37, 0.75);
      }
    }
    for (int i = 1; i < n; ++i)
      for (int a = 0; a < 2; ++a) velocity_[i][a] = c_.slide * (pos_[i][a] - before[i][a]);
  }

  ToyWorldConfig c_;
  std::vector<std::array<double, 2>> pos_, velocity_;
};

// An EpisodeSource that produces `count` toy episodes (seeds base_seed, base_seed + 1, ...),
// a few per Poll, then closes.
class ToySource : public EpisodeSource {
 public:
  ToySource(ToyWorldConfig config, int count, uint64_t base_seed)
      : world_(std::move(config)), count_(count), seed_(base_seed) {}
  bool Poll(std::chrono::milliseconds, std::vector<rl::Episode>* out) override {
    for (int i = 0; i < 50 && produced_ < count_; ++i, ++produced_)
      out->push_back(world_.RandomEpisode(seed_ + produced_));
    return produced_ < count_;
  }

 private:
  ToyWorld world_;
  int count_, produced_ = 0;
  uint64_t seed_;
};

// The episode as one training combination of a catalogue of `num_kinds` entities presents it:
// entity e becomes catalogue entity kinds[e] (its one-hot rewritten), positions unchanged.
// The toy physics of the episode's own pucks is the combination's.
inline rl::Episode AsCombination(const rl::Episode& episode, int num_kinds, const std::vector<uint16_t>& kinds) {
  rl::Episode out = episode;
  const int n = episode.layout.num_entities;
  out.layout = {n, num_kinds, false};
  out.entity_kinds = kinds;
  out.states.clear();
  for (int t = 0; t <= episode.num_steps; ++t)
    for (int e = 0; e < n; ++e) {
      for (int k = 0; k < num_kinds; ++k) out.states.push_back(k == kinds[e] ? 1.f : 0.f);
      out.states.push_back(episode.layout.x(episode.state(t), e));
      out.states.push_back(episode.layout.y(episode.state(t), e));
    }
  return out;
}

// Episodes a test feeds in (push to `queue`), 20 per Poll; never closes.
class FeedSource : public EpisodeSource {
 public:
  bool Poll(std::chrono::milliseconds, std::vector<rl::Episode>* out) override {
    for (int i = 0; i < 20 && !queue.empty(); ++i) {
      out->push_back(std::move(queue.front()));
      queue.pop_front();
    }
    ++polls;
    return true;
  }
  std::deque<rl::Episode> queue;
  int polls = 0;
};

// A GraphSink that remembers what it was given.
class RecordingSink : public GraphSink {
 public:
  void Publish(const rl::GraphUpdate& graph) override { graphs.push_back(graph); }
  void PublishStatus(const rl::NodeReport& report) override { statuses.push_back(report); }
  std::vector<rl::GraphUpdate> graphs;
  std::vector<rl::NodeReport> statuses;
};

}  // namespace srics::graph_service::testing
