// srics-train CONFIG [--set key.path=value ...] [--out DIR] [--graph graph.json]
// Trains one method in one process (environment, policy and learner together) and leaves a
// run folder with curve.csv, curve.png, the effective config and a checkpoint.

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "common/config/config.h"
#include "graph_service/learned_graph.h"
#include "learner/trainer/in_process_trainer.h"

namespace {

int Usage() {
  std::cerr << "usage: srics-train CONFIG [--set key.path=value ...] [--out DIR] [--graph graph.json]\n"
               "  --graph: a graph file of the graph service (default: the preset's ground-truth graph)\n";
  return 2;
}

std::string Timestamp() {
  std::time_t now = std::time(nullptr);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y%m%d-%H%M%S", std::localtime(&now));
  return buffer;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace srics;
  if (argc < 2) return Usage();
  std::string config_path = argv[1];
  std::vector<std::string> overrides;
  std::string out;
  std::string graph_path;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--set" && i + 1 < argc) overrides.push_back(argv[++i]);
    else if (arg == "--out" && i + 1 < argc) out = argv[++i];
    else if (arg == "--graph" && i + 1 < argc) graph_path = argv[++i];
    else return Usage();
  }
  config::Config config;
  try {
    config = config::LoadConfig(config_path, overrides);
  } catch (const config::ConfigError& e) {
    std::cerr << "srics-train: " << e.what() << "\n";
    return 2;
  }
  if (out.empty()) out = config.run.output_dir + "/" + config.run.name + "-" + Timestamp();
  std::filesystem::create_directories(out);
  std::ofstream(out + "/config.yaml") << config.effective_yaml << "\n";
  std::cerr << "srics-train: " << config::MethodName(config.run.method) << ", "
            << config.run.total_env_steps << " env steps, run folder " << out << "\n";

  trainer::TrainerOptions options;
  options.run_dir = out;
  std::optional<graph::LearnedGraph> learned;
  if (!graph_path.empty()) {
    try {
      learned = graph::LoadGraph(graph_path);
    } catch (const std::exception& e) {
      std::cerr << "srics-train: " << e.what() << "\n";
      return 2;
    }
    options.graph = &learned->graph;
    std::cerr << "srics-train: graph from " << graph_path << ": " << rl::DescribeGraph(learned->graph) << "\n";
  }
  options.on_progress = [](const trainer::Progress& p) {
    std::fprintf(stderr, "steps %llu/%llu (%.0f/s)  updates %llu (%.1f/s)  alpha %.3f  q_loss %.4f",
                 (unsigned long long)p.env_steps, (unsigned long long)p.total_env_steps,
                 p.steps_per_second, (unsigned long long)p.updates, p.updates_per_second, p.alpha,
                 p.q_loss);
    if (p.last_eval)
      std::fprintf(stderr, "  eval@%llu avg_obj %.4f avg %.4f (passive %.4f / %.4f)",
                   (unsigned long long)p.last_eval->env_steps, p.last_eval->summary.avg_object_distance,
                   p.last_eval->summary.avg_distance, p.passive->avg_object_distance,
                   p.passive->avg_distance);
    std::fprintf(stderr, "\n");
  };
  trainer::TrainResult result;
  try {
    result = trainer::TrainInProcess(config, options);
  } catch (const std::exception& e) {
    std::cerr << "srics-train: " << e.what() << "\n";
    return 1;
  }
  const auto& last = result.curve.back().summary;
  std::printf("%-28s %12s %12s\n", "final evaluation", "policy", "passive");
  std::printf("%-28s %12.4f %12.4f\n", "avg_object_distance", last.avg_object_distance,
              result.passive.avg_object_distance);
  std::printf("%-28s %12.4f %12.4f\n", "avg_distance", last.avg_distance, result.passive.avg_distance);
  std::printf("%-28s %12.3f %12.3f\n", "success_rate", last.success_rate, result.passive.success_rate);
  for (size_t i = 0; i < last.subgoal_success.size(); ++i)
    std::printf("subgoal %-20zu %12.3f %12.3f\n", i, last.subgoal_success[i], result.passive.subgoal_success[i]);
  std::printf("env steps %llu, updates %llu, %.0f s, unstable episodes %llu\nrun folder: %s\n",
              (unsigned long long)result.env_steps, (unsigned long long)result.updates,
              result.wall_seconds, (unsigned long long)result.unstable_episodes, out.c_str());
  return 0;
}
