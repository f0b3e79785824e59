// srics-learn-graph: learns the interaction graph of an environment in process (no DDS):
// random-action episodes from the MuJoCo environment -> GraphService -> DIR/graph.json,
// graph.png, graph_weights.png, and a progress log on stdout.
//
//   srics-learn-graph --env deploy/configs/env/relational-4.yaml --seed 1 --out DIR
//                     [--set graph.max_updates=6000 ...]
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "actor/env/rearrange_env.h"
#include "actor/rollout.h"
#include "common/config/config.h"
#include "graph_service/service.h"

namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop.store(true); }

// Episodes straight from an environment; episode i uses seed base + i.
class EnvSource : public srics::graph::EpisodeSource {
 public:
  EnvSource(srics::env::Environment& env, int steps, uint64_t seed)
      : env_(env), steps_(steps), seed_(seed), rng_(seed) {}
  bool Poll(std::chrono::milliseconds, std::vector<srics::rl::Episode>* out) override {
    for (int i = 0; i < 10; ++i) {
      auto episode = srics::actor::RunExploreEpisode(env_, steps_, seed_ * 1000003 + next_++, rng_);
      if (episode) out->push_back(std::move(*episode));  // unstable physics: skipped
    }
    return true;
  }

 private:
  srics::env::Environment& env_;
  int steps_;
  uint64_t seed_, next_ = 0;
  srics::nn::Rng rng_;
};

class PrintSink : public srics::graph::GraphSink {
 public:
  void Publish(const srics::graph::LearnedGraph& g) override {
    std::printf("published graph version %llu: %s\n", static_cast<unsigned long long>(g.version),
                srics::rl::DescribeGraph(g.graph).c_str());
  }
};

int Usage() {
  std::fprintf(stderr, "usage: srics-learn-graph --env FILE.yaml --out DIR [--seed N] "
                       "[--set key.path=value ...]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string env_file, out_dir;
  uint64_t seed = 1;
  std::vector<std::string> overrides;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 >= argc) return Usage();
    if (arg == "--env") env_file = argv[++i];
    else if (arg == "--out") out_dir = argv[++i];
    else if (arg == "--seed") seed = std::stoull(argv[++i]);
    else if (arg == "--set") overrides.push_back(argv[++i]);
    else return Usage();
  }
  if (env_file.empty() || out_dir.empty()) return Usage();
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  try {
    const srics::config::Config config = srics::config::LoadConfig(env_file, overrides);
    srics::env::RearrangeEnv env(config.env);
    EnvSource source(env, config.graph.episode_steps, seed);
    PrintSink sink;
    srics::graph::ServiceOptions options;
    options.state_dir = out_dir;
    options.seed = seed;
    srics::graph::GraphService service(
        config.graph, options, &source, &sink, [](const srics::graph::Progress& p) {
          std::printf("[%7.1fs] %-10s episodes %d/%d (dropped %d) updates %lld held-out %.3g "
                      "(no-motion %.3g) stable %d  %s\n",
                      p.elapsed_seconds, srics::graph::PhaseName(p.phase), p.episodes,
                      p.target_episodes, p.dropped, static_cast<long long>(p.updates),
                      p.held_out_loss, p.held_out_zero_loss, p.stable_evaluations,
                      p.graph.c_str());
          const int n = static_cast<int>(std::sqrt(p.mean_weights.size()) + 0.5);
          for (int i = 0; i < n && p.phase == srics::graph::Progress::Phase::kTraining; ++i) {
            std::printf("            ");
            for (int j = 0; j < n; ++j) std::printf(" %.3f", p.mean_weights[i * n + j]);
            std::printf("\n");
          }
          std::fflush(stdout);
        });
    return service.Run(g_stop);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "srics-learn-graph: %s\n", e.what());
    return 1;
  }
}
