// Development tool (not a test): random-action episodes of a real environment, cached in a
// file so that training variants can be compared on the same data, motion statistics, and
// a GraphService run with progress.
//   graph_probe ENV.yaml EPISODES SEED [--stats-only] [--set graph.key=value ...]
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <mujoco/mujoco.h>

#include "actor/env/rearrange_env.h"
#include "actor/explore_episode.h"
#include "common/config/config.h"
#include "graph_service/gnn_model.h"
#include "graph_service/service.h"
#include "tests/graph_service/progress_printer.h"
#include "tests/graph_service/toy_world.h"

using namespace srics;

namespace {

template <typename V>
void WriteVec(std::ofstream& f, const std::vector<V>& v) {
  const uint64_t n = v.size();
  f.write(reinterpret_cast<const char*>(&n), sizeof n);
  f.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(n * sizeof(V)));
}
template <typename V>
void ReadVec(std::ifstream& f, std::vector<V>* v) {
  uint64_t n = 0;
  f.read(reinterpret_cast<char*>(&n), sizeof n);
  v->resize(n);
  f.read(reinterpret_cast<char*>(v->data()), static_cast<std::streamsize>(n * sizeof(V)));
}

class VectorSource : public graph_service::EpisodeSource {
 public:
  explicit VectorSource(std::vector<rl::Episode> e) : episodes_(std::move(e)) {}
  bool Poll(std::chrono::milliseconds, std::vector<rl::Episode>* out) override {
    if (next_ >= episodes_.size()) return false;
    for (int i = 0; i < 100 && next_ < episodes_.size(); ++i) out->push_back(episodes_[next_++]);
    return true;
  }

 private:
  std::vector<rl::Episode> episodes_;
  size_t next_ = 0;
};

// distance between the segments a0-a1 and b0-b1 in the plane
double SegmentDistance(const std::array<double, 2>& a0, const std::array<double, 2>& a1,
                       const std::array<double, 2>& b0, const std::array<double, 2>& b1) {
  return graph_service::SegmentDistance(a0[0], a0[1], a1[0], a1[1], b0[0], b0[1], b1[0], b1[1]);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: graph_probe ENV.yaml EPISODES SEED [--stats-only] [--set k=v]\n");
    return 2;
  }
  const std::string env_file = argv[1];
  const int count = std::atoi(argv[2]);
  const uint64_t seed = std::strtoull(argv[3], nullptr, 10);
  bool stats_only = false;
  bool replay = false;  // re-collect, stepping by hand: pose and contacts at unexplained onsets
  std::vector<std::string> overrides;
  for (int i = 4; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--stats-only")
      stats_only = true;
    else if (a == "--set" && i + 1 < argc)
      overrides.push_back(argv[++i]);
    else if (a == "--replay")
      replay = true;
  }
  config::Config cfg = config::LoadConfig(env_file, overrides);
  cfg.graph.episodes = count;
  const std::string cache = "/tmp/graph_probe_" + std::filesystem::path(env_file).stem().string() + "_" +
                            std::to_string(count) + "_" + std::to_string(seed) + ".bin";
  if (replay) {
    env::RearrangeEnv env(cfg.env);
    const mjModel* m = env.model();
    const int n = env.layout().num_entities;
    const std::vector<double> radius = graph_service::ServiceOptionsFor(cfg, rl::RunShapeFor(cfg), "").contact_radius;
    int shown = 0;
    double clear_onsets = 0, airborne = 0, steps_done = 0;
    for (int ep = 0; ep < 200; ++ep) {
      env.Reset(seed * 1000003 + ep);
      nn::Rng rng(seed + ep);
      std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
      std::vector<env::Vec2> prev = env.Positions(), now = prev;
      std::vector<double> prev_move(n, 0);
      for (int t = 0; t < cfg.graph.episode_steps; ++t) {
        const double action[2] = {uniform(rng), uniform(rng)};
        if (env.Step(action) != env::StepStatus::kOk) break;
        now = env.Positions();
        mjData* d = env.data();
        steps_done += 1;
        if (getenv("TRACE") && ep == atoi(getenv("TRACE")) && std::abs(t - atoi(getenv("TRACE_T"))) <= 3) {
          std::printf("t=%d (state after the step):", t);
          for (int j = 0; j < n; ++j) {
            const int body = j == 0 ? mj_name2id(m, mjOBJ_BODY, "hand")
                                    : mj_name2id(m, mjOBJ_BODY, ("object" + std::to_string(j)).c_str());
            const int dof = m->body_dofadr[body];
            std::printf("  %d: (%.3f %.3f %.4f) v (%.2f %.2f %.2f)", j, d->xpos[3 * body], d->xpos[3 * body + 1],
                        d->xpos[3 * body + 2], d->qvel[dof], d->qvel[dof + 1], d->qvel[dof + 2]);
          }
          std::printf("\n");
        }
        // an object in the air: above its resting height with no contact at all
        for (int j = 1; j < n; ++j) {
          const int body = mj_name2id(m, mjOBJ_BODY, ("object" + std::to_string(j)).c_str());
          bool touching = false;
          for (int c = 0; c < d->ncon && !touching; ++c)
            touching = m->geom_bodyid[d->contact[c].geom1] == body || m->geom_bodyid[d->contact[c].geom2] == body;
          airborne += !touching;
        }
        for (int j = 1; j < n; ++j) {
          const double mv = std::hypot(now[j][0] - prev[j][0], now[j][1] - prev[j][1]);
          if (t > 0 && mv > 1e-3 && prev_move[j] <= 1e-3) {
            bool clear = true;
            for (int i = 0; i < n && clear; ++i)
              if (i != j)
                clear = SegmentDistance({prev[i][0], prev[i][1]}, {now[i][0], now[i][1]}, {prev[j][0], prev[j][1]},
                                        {now[j][0], now[j][1]}) -
                            radius[i] - radius[j] >
                        0.02;
            clear_onsets += clear;
            if (clear && shown < (getenv("SHOWN") ? atoi(getenv("SHOWN")) : 30)) {
              ++shown;
              const int body = mj_name2id(m, mjOBJ_BODY, ("object" + std::to_string(j)).c_str());
              const mjtNum* xq = d->xquat + 4 * body;
              std::printf("onset of %d, episode %d step %d: moved %.4f, z %.4f, quat %.3f %.3f %.3f %.3f, contacts:", j,
                          ep, t, mv, d->xpos[3 * body + 2], xq[0], xq[1], xq[2], xq[3]);
              for (int c = 0; c < d->ncon; ++c) {
                const mjContact& k = d->contact[c];
                const int b1 = m->geom_bodyid[k.geom1], b2 = m->geom_bodyid[k.geom2];
                if (b1 == body || b2 == body) {
                  const char* o = mj_id2name(m, mjOBJ_GEOM, b1 == body ? k.geom2 : k.geom1);
                  std::printf(" %s(%.4f)", o ? o : "?", k.dist);
                }
              }
              std::printf("\n");
            }
          }
          prev_move[j] = mv;
        }
        prev_move[0] = std::hypot(now[0][0] - prev[0][0], now[0][1] - prev[0][1]);
        prev = now;
      }
    }
    std::printf("%g steps: onsets clear of everything by 4 cm %g, object-steps without any contact %g\n", steps_done,
                clear_onsets, airborne);
    return 0;
  }
  std::vector<rl::Episode> episodes;
  if (std::ifstream f{cache, std::ios::binary}) {
    uint64_t n = 0;
    f.read(reinterpret_cast<char*>(&n), sizeof n);
    episodes.resize(n);
    for (auto& e : episodes) {
      f.read(reinterpret_cast<char*>(&e.layout), sizeof e.layout);
      f.read(reinterpret_cast<char*>(&e.num_steps), sizeof e.num_steps);
      f.read(reinterpret_cast<char*>(&e.action_dim), sizeof e.action_dim);
      ReadVec(f, &e.entity_kinds);
      ReadVec(f, &e.states);
      ReadVec(f, &e.actions);
    }
    std::printf("loaded %zu episodes from %s\n", episodes.size(), cache.c_str());
  } else {
    env::RearrangeEnv env(cfg.env);
    nn::Rng rng(seed);
    for (uint64_t i = 0; static_cast<int>(episodes.size()) < count; ++i) {
      auto e = actor::RunExploreEpisode(env, cfg.graph.episode_steps, seed * 1000003 + i, rng);
      if (e) episodes.push_back(std::move(*e));
    }
    std::ofstream o(cache, std::ios::binary);
    const uint64_t n = episodes.size();
    o.write(reinterpret_cast<const char*>(&n), sizeof n);
    for (const auto& e : episodes) {
      o.write(reinterpret_cast<const char*>(&e.layout), sizeof e.layout);
      o.write(reinterpret_cast<const char*>(&e.num_steps), sizeof e.num_steps);
      o.write(reinterpret_cast<const char*>(&e.action_dim), sizeof e.action_dim);
      WriteVec(o, e.entity_kinds);
      WriteVec(o, e.states);
      WriteVec(o, e.actions);
    }
    std::printf("collected %zu episodes into %s\n", episodes.size(), cache.c_str());
  }
  // motion statistics: fraction of transitions in which each entity moves > 1 mm, and the
  // fraction of 20-step windows with some non-arm motion
  const rl::EntityLayout& l = episodes[0].layout;
  const int n = l.num_entities, steps = episodes[0].num_steps;
  std::vector<double> moved(n, 0), sq(n, 0);
  double transitions = 0, windows = 0, windows_moving = 0;
  for (const auto& e : episodes) {
    std::vector<int> any(steps, 0);
    for (int t = 0; t < steps; ++t) {
      for (int j = 0; j < n; ++j) {
        const double dx = l.x(e.state(t + 1), j) - l.x(e.state(t), j);
        const double dy = l.y(e.state(t + 1), j) - l.y(e.state(t), j);
        const double d = std::sqrt(dx * dx + dy * dy);
        if (d > 1e-3) {
          moved[j] += 1;
          if (j > 0) any[t] = 1;
        }
        sq[j] += d * d;
      }
      transitions += 1;
    }
    for (int s = 0; s + 20 <= steps; ++s) {
      int m = 0;
      for (int t = s; t < s + 20; ++t) m |= any[t];
      windows += 1;
      windows_moving += m;
    }
  }
  std::printf("fraction of transitions with motion > 1 mm (rms step):");
  for (int j = 0; j < n; ++j)
    std::printf(" %d: %.4f (%.4f m)", j, moved[j] / transitions, std::sqrt(sq[j] / transitions));
  std::printf("\nfraction of 20-step windows with some puck motion: %.3f\n", windows_moving / windows);
  // onsets (moving > 1 mm after a step that did not) per entity, and those with every other
  // entity farther than its closest approach in the data + 2 cm before and after the step
  // (what graph.onset_loss_weight emphasises)
  {
    std::vector<double> closest(n * n, 1e9);
    for (const auto& e : episodes)
      for (int t = 0; t <= steps; ++t)
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j)
            if (i != j)
              closest[i * n + j] = std::min(
                  closest[i * n + j],
                  (double)std::hypot(l.x(e.state(t), i) - l.x(e.state(t), j), l.y(e.state(t), i) - l.y(e.state(t), j)));
    std::vector<double> onsets(n, 0), clear(n, 0);
    for (const auto& e : episodes)
      for (int t = 1; t < steps; ++t)
        for (int j = 0; j < n; ++j) {
          auto step = [&](int k, int s) {
            return std::hypot(l.x(e.state(s + 1), k) - l.x(e.state(s), k), l.y(e.state(s + 1), k) - l.y(e.state(s), k));
          };
          if (!(step(j, t) > 1e-3 && step(j, t - 1) <= 1e-3)) continue;
          onsets[j] += 1;
          bool ok = true;
          for (int i = 0; i < n && ok; ++i) {
            if (i == j) continue;
            for (int s : {t, t + 1})
              ok = ok && std::hypot(l.x(e.state(s), i) - l.x(e.state(s), j), l.y(e.state(s), i) - l.y(e.state(s), j)) >
                             (getenv("CLEAR") ? atof(getenv("CLEAR")) : closest[i * n + j] + 0.02);
          }
          clear[j] += ok;
        }
    std::printf("closest approach:");
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) std::printf(" %d-%d %.3f", i, j, closest[i * n + j]);
    std::printf("\n");
    std::printf("onsets per entity (fraction of transitions; clear of every other entity):");
    for (int j = 0; j < n; ++j) std::printf(" %d: %.4f (%.4f)", j, onsets[j] / transitions, clear[j] / transitions);
    std::printf("\n");
  }
  // motion the arm did not cause directly: object j moves > 1 mm while the arm is farther than
  // 12 cm from it before and after the step; then, per other object i, how often i moved in the same step or was within
  // 7 cm (contact or tie at work). A tie that never shows here cannot be learned from the data.
  auto dist = [&](const float* s, int a, int b) { return std::hypot(l.x(s, a) - l.x(s, b), l.y(s, a) - l.y(s, b)); };
  std::printf(
      "motion without the arm within 12 cm (fraction of transitions); per other object i: [i moved too / i within 7 "
      "cm]\n");
  for (int j = 1; j < n; ++j) {
    double alone = 0;
    std::vector<double> with_moving(n, 0), with_near(n, 0);
    for (const auto& e : episodes) {
      for (int t = 0; t < steps; ++t) {
        const float* a = e.state(t);
        const float* b = e.state(t + 1);
        auto moved_by = [&](int k) { return std::hypot(l.x(b, k) - l.x(a, k), l.y(b, k) - l.y(a, k)) > 1e-3; };
        if (!moved_by(j) || std::min(dist(a, 0, j), dist(b, 0, j)) < 0.12) continue;
        alone += 1;
        for (int i = 1; i < n; ++i) {
          if (i == j) continue;
          with_moving[i] += moved_by(i);
          with_near[i] += dist(a, i, j) < 0.07;
        }
      }
    }
    std::printf("  %d: %.5f", j, alone / transitions);
    for (int i = 1; i < n; ++i)
      if (i != j && alone > 0) std::printf("  %d:[%.2f/%.2f]", i, with_moving[i] / alone, with_near[i] / alone);
    std::printf("\n");
  }
  // how far each tie is stretched: the fraction of steps at each distance beyond (or short of)
  // its length, and how often the partner moved > 1 mm then (a spring needs stretch to pull
  // against friction; a rope pulls at its length)
  for (const auto& link : cfg.env.connections) {
    const int a = link.first, b = link.second;
    const double bins[] = {-1, -0.03, 0, 0.01, 0.03, 0.05, 1};
    std::vector<double> count(6, 0), partner_moved(6, 0);
    // the partner's squared motion, all of it and the part with the arm >= 12 cm away (what a
    // squared-error loss can credit to the tie or contacts only), and its rms step then
    double sq_all = 0, sq_far = 0, steps_far = 0;
    for (const auto& e : episodes)
      for (int t = 0; t < steps; ++t) {
        {
          const float* s0 = e.state(t);
          const float* s1 = e.state(t + 1);
          const double d2 = std::pow(l.x(s1, b) - l.x(s0, b), 2) + std::pow(l.y(s1, b) - l.y(s0, b), 2);
          sq_all += d2;
          if (std::min(dist(s0, 0, b), dist(s1, 0, b)) >= 0.12 && d2 > 1e-6) sq_far += d2, steps_far += 1;
        }
        const double over = dist(e.state(t), a, b) - link.length;
        const float* s0 = e.state(t);
        const float* s1 = e.state(t + 1);
        const bool moved_b = std::hypot(l.x(s1, b) - l.x(s0, b), l.y(s1, b) - l.y(s0, b)) > 1e-3;
        for (int k = 0; k < 6; ++k)
          if (over >= bins[k] && over < bins[k + 1]) count[k] += 1, partner_moved[k] += moved_b;
      }
    std::printf("tie %d-%d (length %.3f): distance minus length [fraction of steps, %d moved]:", a, b, link.length, b);
    const char* names[] = {"< -3cm", "-3..0cm", "0..1cm", "1..3cm", "3..5cm", ">= 5cm"};
    for (int k = 0; k < 6; ++k)
      std::printf("  %s [%.4f, %.2f]", names[k], count[k] / transitions,
                  count[k] > 0 ? partner_moved[k] / count[k] : 0.0);
    std::printf("\n");
    std::printf(
        "  partner %d: share of its squared motion with the arm >= 12 cm away %.3f (%.4f of steps, rms step then %.4f "
        "m)\n",
        b, sq_all > 0 ? sq_far / sq_all : 0.0, steps_far / transitions,
        steps_far > 0 ? std::sqrt(sq_far / steps_far) : 0.0);
  }
  // the onsets graph.onset_loss_weight weights (the arm's, pushes and collisions left out by
  // the clearances of GnnTrainer), per object; and of those, how many some other object could
  // have touched within the step all the same: its gap before the step is under the distance it
  // travelled in the step or the one before (a fast object hits and bounces back within a step)
  {
    const std::vector<double> radius = graph_service::ServiceOptionsFor(cfg, rl::RunShapeFor(cfg), "").contact_radius;
    std::vector<double> weighted(n, 0), reachable(n * n, 0), unreached(n, 0), swept(n, 0);
    int shown = 0;
    for (const auto& e : episodes)
      for (int t = 1; t < steps; ++t) {
        auto move = [&](int k, int s) {
          return std::hypot(l.x(e.state(s + 1), k) - l.x(e.state(s), k), l.y(e.state(s + 1), k) - l.y(e.state(s), k));
        };
        for (int j = 1; j < n; ++j) {
          if (!(move(j, t) > cfg.graph.onset_motion_m && move(j, t - 1) <= cfg.graph.onset_motion_m)) continue;
          bool clear = true;
          for (int i = 0; i < n && clear; ++i) {
            if (i == j) continue;
            const double c =
                radius[i] + radius[j] + (i == 0 ? cfg.graph.contact_margin_m : cfg.graph.object_contact_margin_m);
            clear = dist(e.state(t), i, j) > c && dist(e.state(t + 1), i, j) > c;
          }
          if (!clear) continue;
          // the swept rule: the two paths of the step (straight segments) never within contact
          bool swept_clear = true;
          for (int i = 0; i < n && swept_clear; ++i) {
            if (i == j) continue;
            const double c =
                radius[i] + radius[j] + (i == 0 ? cfg.graph.contact_margin_m : cfg.graph.object_contact_margin_m);
            auto P = [&](int k, int s) { return std::array<double, 2>{l.x(e.state(s), k), l.y(e.state(s), k)}; };
            swept_clear = SegmentDistance(P(i, t), P(i, t + 1), P(j, t), P(j, t + 1)) > c;
          }
          swept[j] += swept_clear;
          weighted[j] += 1;
          bool anyone = false;
          for (int i = 0; i < n; ++i) {
            if (i == j) continue;
            const double gap = dist(e.state(t), i, j) - radius[i] - radius[j];
            if (gap < std::max(move(i, t), move(i, t - 1))) reachable[i * n + j] += 1, anyone = true;
          }
          unreached[j] += !anyone;
          if (!anyone && j == n - 1 && getenv("SHOW") && shown++ < 25) {
            double nearest = 1e9, ngap = 0;
            int who = -1;
            for (int i = 0; i < n; ++i)
              if (i != j)
                for (int s = std::max(0, t - 2); s <= t + 1; ++s) {
                  const double gap = dist(e.state(s), i, j) - radius[i] - radius[j];
                  if (gap < nearest) nearest = gap, who = i, ngap = s - t;
                }
            std::printf(
                "    unreached onset of %d at t=%d: moves %.5f -> %.5f (before: %.5f), nearest gap %.4f by %d at step "
                "%+g, travel of %d: %.4f %.4f %.4f\n",
                j, t, move(j, t - 1), move(j, t), t >= 2 ? move(j, t - 2) : -1.0, nearest, who, ngap, who,
                t >= 2 ? move(who, t - 2) : -1.0, move(who, t - 1), move(who, t));
            // the arm's segment from t to t+1: closest approach of its centre to j's start
            const double ax = l.x(e.state(t), 0), ay = l.y(e.state(t), 0), bx = l.x(e.state(t + 1), 0),
                         by = l.y(e.state(t + 1), 0);
            const double px = l.x(e.state(t), j), py = l.y(e.state(t), j);
            const double len2 = (bx - ax) * (bx - ax) + (by - ay) * (by - ay);
            const double u =
                len2 > 0 ? std::clamp(((px - ax) * (bx - ax) + (py - ay) * (by - ay)) / len2, 0.0, 1.0) : 0.0;
            std::printf(
                "      arm gap at t-1 %.4f t %.4f t+1 %.4f, on the segment %.4f; j at (%.3f, %.3f) -> (%.3f, %.3f)\n",
                dist(e.state(t - 1), 0, j) - radius[0] - radius[j], dist(e.state(t), 0, j) - radius[0] - radius[j],
                dist(e.state(t + 1), 0, j) - radius[0] - radius[j],
                std::hypot(ax + u * (bx - ax) - px, ay + u * (by - ay) - py) - radius[0] - radius[j], px, py,
                l.x(e.state(t + 1), j), l.y(e.state(t + 1), j));
          }
        }
      }
    std::printf("weighted onsets per object (fraction of transitions) [reachable within the step by i: count]:\n");
    for (int j = 1; j < n; ++j) {
      std::printf("  %d: %.5f (%g, %g reachable by nobody, %g with every path of the step apart)", j,
                  weighted[j] / transitions, weighted[j], unreached[j], swept[j]);
      for (int i = 0; i < n; ++i)
        if (i != j) std::printf("  %d:%g", i, reachable[i * n + j]);
      std::printf("\n");
    }
  }
  if (stats_only) return 0;

  VectorSource source(std::move(episodes));
  graph_service::testing::RecordingSink sink;
  graph_service::ServiceOptions options;
  options.seed = seed;
  options.render_pictures = false;
  options.contact_radius = graph_service::ServiceOptionsFor(cfg, rl::RunShapeFor(cfg), "").contact_radius;
  options.state_dir = "/tmp/graph_probe_out_" + std::filesystem::path(env_file).stem().string() + "_" +
                      std::to_string(seed) + "_" + std::to_string(getpid());
  std::filesystem::remove_all(options.state_dir);
  graph_service::GraphService service(cfg.graph, options, &source, &sink,
                                      graph_service::testing::PrintTrainingProgress);
  std::atomic<bool> stop{false};
  const int rc = service.Run(stop);
  if (!sink.graphs.empty()) std::printf("FINAL %s\n", rl::DescribeGraph(sink.graphs[0].graph).c_str());
  return rc;
}
