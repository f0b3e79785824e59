#include "learner/trainer/in_process_trainer.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>

#include "actor/env/rearrange_env.h"
#include "actor/ground_truth.h"
#include "actor/rollout.h"
#include "common/rl/agent_shape.h"
#include "learner/learner.h"

namespace srics::trainer {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

rl::EvaluationSummary Evaluate(env::Environment& env, rl::PolicyNetwork<float>* policy,
                               const rl::SubgoalStructure& structure, const actor::EvalOptions& options,
                               const config::Config& config, uint64_t* unstable) {
  rl::EvaluationSummary summary;
  for (int i = 0; i < config.actors.eval_episodes; ++i) {
    auto metrics = actor::RunEvaluationEpisode(env, policy, structure, options, actor::EvalSeed(config.run.seed, i));
    if (!metrics) {
      ++*unstable;
      continue;
    }
    summary.Add(*metrics, options.threshold);
  }
  return summary;
}

}  // namespace

TrainResult TrainInProcess(const config::Config& config, const TrainerOptions& options) {
  const auto start = Clock::now();
  TrainResult result;
  std::unique_ptr<env::Environment> env = env::MakeRearrangeEnv(config.env);
  learner::Learner learner(config);

  const config::Method method = config.run.method;
  const bool uses_graph = rl::UsesGraph(method);
  const rl::InteractionGraph graph = options.graph ? *options.graph : actor::GroundTruthGraph(config.env);
  const int num_entities = graph.num_entities;
  const int env_entities = 1 + static_cast<int>(config::EffectiveObjects(config.env).size());
  if (num_entities != env_entities)
    throw std::invalid_argument("the graph has " + std::to_string(num_entities) + " entities, the environment " +
                                std::to_string(env_entities));
  // SMORL and SAC+HER know no graph: every entity is a subgoal with no ancestors
  const rl::SubgoalStructure structure =
      uses_graph ? rl::ComputeSubgoalStructure(graph) : rl::AllEntitiesStructure(num_entities);
  learner.SetGraph(structure);

  const actor::TrainOptions train = actor::TrainOptionsFor(config);
  const actor::EvalOptions eval = actor::EvalOptionsFor(config);

  result.passive = Evaluate(*env, nullptr, structure, eval, config, &result.unstable_episodes);

  nn::Rng rng(config.run.seed * 2654435761ull + 3);
  uint64_t episode_index = 0;
  uint64_t next_eval = config.actors.eval_every_env_steps;
  auto last_progress = Clock::now();
  uint64_t steps_at_progress = 0, updates_at_progress = 0;
  learner::UpdateStats last_stats;
  const double wall_limit = config.run.max_wall_minutes * 60.0;

  auto evaluate_now = [&]() {
    EvalPoint point;
    point.env_steps = result.env_steps;
    point.updates = learner.counters().updates;
    point.summary = Evaluate(*env, &learner.agent().policy(), structure, eval, config, &result.unstable_episodes);
    point.wall_seconds = Seconds(start);
    result.curve.push_back(point);
  };

  while (result.env_steps < config.run.total_env_steps) {
    if (wall_limit > 0 && Seconds(start) > wall_limit) break;
    const uint64_t seed = config.run.seed * 1000003ull + episode_index++;
    // random exploration fills the warm-up, then the policy acts on subgoals
    std::optional<rl::Episode> episode;
    if (result.env_steps < config.learner.warmup_steps)
      episode = actor::RunExploreEpisode(*env, config.actors.explore_episode_steps, seed, rng);
    else
      episode = actor::RunTrainEpisode(*env, learner.agent().policy(), structure, train, seed, rng);
    if (!episode) {
      ++result.unstable_episodes;
      continue;
    }
    result.env_steps += episode->num_steps;
    const std::string problem = learner.Ingest(std::move(*episode));
    if (!problem.empty()) throw std::logic_error("the trainer's own episode was rejected: " + problem);
    while (learner.CanUpdate()) last_stats = learner.Update();

    if (result.env_steps >= next_eval) {
      next_eval += config.actors.eval_every_env_steps;
      evaluate_now();
    }
    if (options.on_progress && Seconds(last_progress) >= options.progress_seconds) {
      const double dt = Seconds(last_progress);
      Progress p;
      p.env_steps = result.env_steps;
      p.total_env_steps = config.run.total_env_steps;
      p.updates = learner.counters().updates;
      p.steps_per_second = (result.env_steps - steps_at_progress) / dt;
      p.updates_per_second = (p.updates - updates_at_progress) / dt;
      p.alpha = last_stats.alpha;
      p.q_loss = last_stats.q_loss;
      p.last_eval = result.curve.empty() ? nullptr : &result.curve.back();
      p.passive = &result.passive;
      options.on_progress(p);
      last_progress = Clock::now();
      steps_at_progress = result.env_steps;
      updates_at_progress = p.updates;
    }
  }
  if (result.curve.empty() || result.curve.back().env_steps != result.env_steps) evaluate_now();
  result.updates = learner.counters().updates;
  result.wall_seconds = Seconds(start);

  if (!options.run_dir.empty()) {
    std::filesystem::create_directories(options.run_dir);
    learner.SaveCheckpoint(options.run_dir + "/checkpoint.srics");
    WriteCurveCsv(options.run_dir + "/curve.csv", result);
    PlotCurve(options.run_dir + "/curve.csv", options.run_dir + "/curve.png",
              std::string(config::MethodName(method)) + " on " + config.source_file);
  }
  return result;
}

void WriteCurveCsv(const std::string& path, const TrainResult& result) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "env_steps,updates,wall_seconds,avg_distance,avg_object_distance,success_rate,selectivity,"
         "passive_avg_distance,passive_avg_object_distance";
  const size_t n = result.passive.entity_distance.size();
  for (size_t i = 0; i < n; ++i) out << ",distance_" << i;
  for (size_t i = 0; i < n; ++i) out << ",subgoal_success_" << i;
  out << "\n" << std::setprecision(6);
  for (const EvalPoint& p : result.curve) {
    const auto& s = p.summary;
    out << p.env_steps << "," << p.updates << "," << p.wall_seconds << "," << s.avg_distance << ","
        << s.avg_object_distance << "," << s.success_rate << ","
        << (s.selectivity_episodes ? s.selectivity : 0.0) << "," << result.passive.avg_distance << ","
        << result.passive.avg_object_distance;
    for (size_t i = 0; i < n; ++i) out << "," << (i < s.entity_distance.size() ? s.entity_distance[i] : 0.0);
    for (size_t i = 0; i < n; ++i) out << "," << (i < s.subgoal_success.size() ? s.subgoal_success[i] : 0.0);
    out << "\n";
  }
}

bool PlotCurve(const std::string& csv_path, const std::string& png_path, const std::string& title) {
  const std::string script_path = png_path + ".gnuplot";
  {
    std::ofstream script(script_path);
    script << "set datafile separator ','\n"
           << "set terminal pngcairo size 900,540 font 'sans,10'\n"
           << "set output '" << png_path << "'\n"
           << "set title '" << title << "' noenhanced\n"
           << "set xlabel 'environment steps'\nset ylabel 'final distance to goal (m)'\n"
           << "set key outside right top\nset grid\nset yrange [0:*]\n"
           << "plot '" << csv_path << "' skip 1 using 1:5 with linespoints lw 2 title 'avg object distance', \\\n"
           << "     '' skip 1 using 1:4 with linespoints lw 2 title 'avg distance (arm incl.)', \\\n"
           << "     '' skip 1 using 1:9 with lines dt 2 lw 2 title 'passive: avg object distance', \\\n"
           << "     '' skip 1 using 1:8 with lines dt 3 lw 2 title 'passive: avg distance'\n";
  }
  const std::string command = "gnuplot '" + script_path + "' 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return false;
  char line[512];
  std::string output;
  while (fgets(line, sizeof line, pipe)) output += line;
  const int status = pclose(pipe);
  if (status != 0) {
    std::fprintf(stderr, "plot: gnuplot failed (%d): %s\n", status, output.c_str());
    return false;
  }
  return true;
}

}  // namespace srics::trainer
