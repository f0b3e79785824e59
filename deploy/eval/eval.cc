#include "deploy/eval/eval.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>

#include "actor/actor_loop.h"
#include "actor/env/rearrange_env.h"
#include "actor/env/render/gl_context.h"
#include "actor/eval_episode.h"
#include "common/config/config.h"
#include "common/graph_file/graph_file.h"
#include "common/rl/agent_shape.h"
#include "common/rl/evaluation.h"
#include "common/rl/ground_truth.h"
#include "common/rl/seeds.h"
#include "deploy/run_folder/csv.h"
#include "deploy/run_folder/schema.h"
#include "learner/acting_policy.h"

namespace srics::eval {

namespace fs = std::filesystem;

namespace {

// The name of an entity in captions.
std::string EntityName(int entity) { return entity == 0 ? "arm" : "object " + std::to_string(entity); }

// "0.80 of 99": part / whole with the whole, for the summary lines.
std::string ShareOf(int part, int whole) {
  char text[48];
  std::snprintf(text, sizeof(text), "%.2f of %d", whole ? static_cast<double>(part) / whole : 0.0, whole);
  return text;
}

// What each attempt did, summed over episodes (printed at the end).
struct AttemptTally {
  int attempts = 0;                    // attempts that took steps
  int reached = 0;                     // ... and ended with their own subgoal within the threshold
  int others_solved = 0;               // objects solved when an attempt started
  int others_undone = 0;               // ... that the attempt left unsolved
  int others_undone_before_moved = 0;  // ... before the attempted entity had moved (Attempt::kMovedM)
  int independent_solved = 0;          // the same over objects that are not the entity's ancestors
  int independent_undone = 0;
  // per other subgoal object: (times it was solved when an attempt started, times the attempt
  // left it unsolved), and of those solved, how many ended beyond twice the threshold (knocked
  // away rather than nudged across it)
  std::map<int, std::pair<int, int>> by_object;
  int pushed_far = 0;
};

// Draws every state of an episode into its video (when there is one) and writes each subgoal
// attempt to attempts.csv.
class EpisodeRecorder : public actor::EvalEpisodeObserver {
 public:
  EpisodeRecorder(env::EpisodeRenderer* renderer, env::VideoWriter* video, std::ostream& attempts,
                  std::map<int, AttemptTally>& tally, double threshold, int episode)
      : renderer_(renderer),
        video_(video),
        attempts_(attempts),
        tally_(tally),
        threshold_(threshold),
        episode_(episode) {}

  void OnState(const env::Environment& env, int entity) override {
    if (!renderer_) return;
    const std::string what = env.steps() == 0 ? "start" : entity < 0 ? "full goal" : "subgoal: " + EntityName(entity);
    const std::string caption =
        "episode " + std::to_string(episode_) + "  step " + std::to_string(env.steps()) + "  " + what;
    video_->Write(renderer_->Render(entity, caption).rgb.data());
  }

  void OnAttempt(const Attempt& a) override {
    const bool reached = a.distance_after < threshold_;
    attempts_ << episode_ << "," << a.index << "," << a.entity << "," << (a.skipped ? 1 : 0) << "," << a.distance_before
              << "," << a.distance_after << "," << (reached ? 1 : 0) << "," << a.others_solved << "," << a.others_undone
              << "," << a.independent_solved << "," << a.independent_undone << ","
              << run_folder::JoinedValues(a.distances_before) << "," << run_folder::JoinedValues(a.distances_after)
              << "," << a.others_undone_before_moved << "\n";
    if (a.skipped) return;
    AttemptTally& t = tally_[a.entity];
    ++t.attempts;
    t.reached += reached ? 1 : 0;
    t.others_solved += a.others_solved;
    t.others_undone += a.others_undone;
    t.others_undone_before_moved += a.others_undone_before_moved;
    t.independent_solved += a.independent_solved;
    t.independent_undone += a.independent_undone;
    for (int other : a.solved_others) {
      auto& [solved, undone] = t.by_object[other];
      ++solved;
      undone += a.distances_after[other] >= threshold_ ? 1 : 0;
      t.pushed_far += a.distances_after[other] >= 2 * threshold_ ? 1 : 0;
    }
  }

 private:
  env::EpisodeRenderer* renderer_;
  env::VideoWriter* video_;
  std::ostream& attempts_;
  std::map<int, AttemptTally>& tally_;
  double threshold_;
  int episode_;
};

// Where the checkpoint, config and graph are.
struct RunFiles {
  std::string dir;
  std::string checkpoint;
  std::string config;
  std::string graph;
};

RunFiles Locate(const EvalArgs& args) {
  RunFiles f;
  std::error_code error;
  if (fs::is_directory(args.target, error)) {
    f.dir = args.target;
    f.checkpoint = (fs::path(args.target) / "checkpoint.srics").string();
  } else if (fs::exists(args.target, error)) {
    f.checkpoint = args.target;
    f.dir = fs::path(args.target).parent_path().string();
    if (f.dir.empty()) f.dir = ".";
  } else {
    throw std::invalid_argument("RUN_DIR|CHECKPOINT: no such folder or file: " + args.target);
  }
  f.config = args.config_file.empty() ? (fs::path(f.dir) / "config.yaml").string() : args.config_file;
  if (!fs::is_regular_file(f.config, error))
    throw std::invalid_argument(args.config_file.empty()
                                    ? "RUN_DIR|CHECKPOINT: no config.yaml in " + f.dir + " (give --config FILE)"
                                    : "--config: no such file: " + args.config_file);
  f.graph = args.graph_file.empty() ? (fs::path(f.dir) / "graph.json").string() : args.graph_file;
  if (!args.graph_file.empty() && !fs::is_regular_file(f.graph, error))
    throw std::invalid_argument("--graph: no such file: " + args.graph_file);
  return f;
}

}  // namespace

int Eval(const EvalArgs& args) {
  const RunFiles files = Locate(args);
  const config::Config config = config::LoadConfig(files.config, args.overrides);
  const int episodes = args.episodes > 0 ? args.episodes : config.actors.eval_episodes;
  const std::string out_dir = args.out_dir.empty() ? (fs::path(files.dir) / "eval").string() : args.out_dir;

  // the acting networks, as an actor of this run builds them
  const rl::RunShape shape = rl::RunShapeFor(config);
  const actor::ActorOptions actor = actor::ActorOptionsFor(config, shape, 0);
  if (!args.protocol.empty() && (actor.eval.full_goal || actor.eval.hac))
    throw std::invalid_argument("--protocol: " + std::string(config::MethodName(config.run.method)) +
                                " attempts the full goal; protocols apply to subgoal policies");
  env::RearrangeEnv environment(actor.env);
  nn::Rng init(0);
  rl::PolicyNetwork<float> policy("policy", actor.policy, init);
  std::unique_ptr<rl::PolicyNetwork<float>> high;
  if (actor.high_policy) high = std::make_unique<rl::PolicyNetwork<float>>("policy", *actor.high_policy, init);
  // the networks that act: none for the passive baseline
  rl::PolicyNetwork<float>* acting = args.passive ? nullptr : &policy;
  rl::PolicyNetwork<float>* acting_high = args.passive ? nullptr : high.get();
  learner::LearnerCounters counters;
  if (!args.passive) {
    if (!fs::exists(files.checkpoint))
      throw std::runtime_error("no checkpoint: " + files.checkpoint +
                               " does not exist (has the run checkpointed yet?)");
    counters = learner::LoadActingPolicies(files.checkpoint, policy, high.get());
  }

  // the subgoals and their order: the run's graph, or every entity for methods without one
  // graphs are over the catalogue; each episode maps it onto the objects it presents
  const int catalogue_entities = shape.entities();
  rl::CatalogueSubgoals subgoals;
  std::string graph_text = "none (" + std::string(config::MethodName(config.run.method)) + " uses no graph)";
  actor::EvalOptions eval_options = actor.eval;
  const bool depth_protocol = args.protocol == "depth";
  if (!args.protocol.empty())
    eval_options.order = depth_protocol ? rl::SubgoalOrder::kDepth : rl::SubgoalOrder::kRandom;
  if (args.protocol == "random") {
    graph_text = "none (--protocol random: every entity, in random order)";
  } else if (depth_protocol && !actor.uses_graph && args.graph_file.empty()) {
    subgoals.graph = rl::GroundTruthGraph(config.env);
    graph_text = rl::DescribeGraph(*subgoals.graph) + " (--protocol depth: the table's graph by construction)";
  } else if (actor.uses_graph || depth_protocol) {
    if (!fs::exists(files.graph))
      throw std::runtime_error("no graph: " + files.graph + " does not exist; " +
                               config::MethodName(config.run.method) +
                               " evaluates in the order of the run's interaction graph (give --graph FILE)");
    const graph_file::LearnedGraph graph = graph_file::LoadGraph(files.graph);
    if (const std::string problem = rl::GraphMismatch(graph.graph, catalogue_entities); !problem.empty())
      throw std::runtime_error(files.graph + ": " + problem);
    subgoals.graph = graph.graph;
    graph_text = rl::DescribeGraph(graph.graph) + " (" + files.graph + ")";
  }
  // the run's networks take a tied pair's two goal tokens (graph.object_ties: joint)
  subgoals.joint_ties = policy.config().goal_tokens > 1;

  // the renderer and the video format
  std::optional<env::GlContext> gl;
  std::optional<env::EpisodeRenderer> renderer;
  env::VideoOptions video;
  video.fps = args.fps;
  if (args.video) {
    if (!args.format.empty()) {
      video.format = *env::ParseVideoFormat(args.format);
    } else if (!env::FfmpegAvailable()) {
      video.format = env::VideoFormat::kPng;
      std::cout << "ffmpeg is not installed: episodes are written as PNG frames "
                   "(deploy/install-deps.sh video installs it)\n";
    }
    gl.emplace();
    renderer.emplace(environment, *gl, args.render);
  }
  fs::create_directories(out_dir);
  if (args.passive)
    std::printf("the passive baseline (--passive): the hand never moves\n");
  else
    std::printf("checkpoint %s: %llu updates, policy v%llu, %llu training env steps\n", files.checkpoint.c_str(),
                static_cast<unsigned long long>(counters.updates),
                static_cast<unsigned long long>(counters.policy_version),
                static_cast<unsigned long long>(counters.training_env_steps));
  const uint64_t goal_seed = args.goal_set ? args.goal_set : config.run.seed;
  std::printf("method %s, graph %s, subgoal order %s, goals of evaluation seed %llu\n",
              config::MethodName(config.run.method), graph_text.c_str(),
              eval_options.full_goal || eval_options.hac       ? "(full goal)"
              : eval_options.order == rl::SubgoalOrder::kDepth ? "depth"
                                                               : "random",
              static_cast<unsigned long long>(goal_seed));
  if (gl) std::printf("renderer: %s\n", gl->description().c_str());

  // one CSV row per episode
  // the subgoal columns: the structure of the first evaluation episode's objects
  environment.Reset(rl::EvalEpisodeSeed(goal_seed, 0), env::Split::kEval);
  // the evaluation's objects (env.eval_object_sets), which may be fewer than the training's
  const int num_entities = environment.layout().num_entities;
  // (a column per entity: a tied pair attempted as one has two)
  rl::CatalogueSubgoals per_entity = subgoals;
  per_entity.joint_ties = false;
  const std::vector<int> subgoal_entities = per_entity.For(environment.layout().kinds).SubgoalEntities();
  std::ofstream csv(fs::path(out_dir) / "episodes.csv");
  csv << run_folder::HeaderLine(run_folder::kEpisodesLeadingColumns);
  for (int e = 0; e < num_entities; ++e) csv << ",distance_" << e;
  for (int e : subgoal_entities) csv << ",subgoal_success_" << e;
  csv << ",video\n";
  std::ofstream attempts_csv(fs::path(out_dir) / "attempts.csv");
  attempts_csv << run_folder::HeaderLine(run_folder::kAttemptsColumns) << "\n";
  std::map<int, AttemptTally> tally;
  rl::EvaluationSummary summary;
  int unstable = 0;
  for (int i = 0; i < episodes; ++i) {
    const uint64_t seed = rl::EvalEpisodeSeed(goal_seed, i);
    std::optional<env::VideoWriter> writer;
    std::string video_name;
    if (renderer) {
      char name[32];
      std::snprintf(name, sizeof(name), "episode-%03d", i);
      video_name = name;
      if (video.format != env::VideoFormat::kPng) video_name += "." + env::VideoExtension(video.format);
      writer.emplace((fs::path(out_dir) / video_name).string(), args.render.width, args.render.height, video);
    }
    EpisodeRecorder recorder(renderer ? &*renderer : nullptr, writer ? &*writer : nullptr, attempts_csv, tally,
                             eval_options.threshold, i);
    const auto metrics =
        actor::RunEvaluationEpisode(environment, acting, subgoals, eval_options, seed, acting_high, &recorder);
    if (writer) writer->Close();
    const int frames = writer ? writer->frames() : 0;
    if (environment.layout().num_entities != num_entities)
      throw std::runtime_error("episode " + std::to_string(i) + " has another number of entities");
    csv << i << "," << seed << "," << (metrics ? "ok" : "unstable") << "," << environment.steps() << "," << frames;
    if (metrics) {
      summary.Add(*metrics, eval_options.threshold);
      csv << "," << metrics->avg_distance << "," << metrics->avg_object_distance << "," << (metrics->success ? 1 : 0)
          << "," << metrics->selectivity << "," << metrics->independent_solved << "," << metrics->independent_undone;
      for (double d : metrics->entity_distance) csv << "," << d;
      for (int e : subgoal_entities) csv << "," << (metrics->entity_distance[e] < eval_options.threshold ? 1 : 0);
      std::printf("episode %d: %d steps, avg distance %.4f, avg object distance %.4f, success %d%s%s\n", i,
                  environment.steps(), metrics->avg_distance, metrics->avg_object_distance, metrics->success ? 1 : 0,
                  video_name.empty() ? "" : " -> ", video_name.c_str());
    } else {
      ++unstable;
      csv << ",,,,,,";
      for (int e = 0; e < num_entities + static_cast<int>(subgoal_entities.size()); ++e) csv << ",";
      std::printf("episode %d: the physics became unstable after %d steps\n", i, environment.steps());
    }
    csv << "," << video_name << "\n";
    csv.flush();
  }
  if (!csv) throw std::runtime_error("cannot write " + (fs::path(out_dir) / "episodes.csv").string());
  std::printf("%d episodes (%d unstable): avg distance %.4f, avg object distance %.4f, success rate %.2f\n", episodes,
              unstable, summary.avg_distance, summary.avg_object_distance, summary.success_rate);
  if (!attempts_csv.flush()) throw std::runtime_error("cannot write " + (fs::path(out_dir) / "attempts.csv").string());
  // per subgoal: can the policy reach it, and does reaching it undo the others?
  for (const auto& [entity, t] : tally)
    std::printf(
        "attempts on %s: %d, reached %.2f; objects solved before them: %d, undone by them: %d (%.2f); of those not "
        "its ancestors: %d, undone %d (%.2f)\n",
        EntityName(entity).c_str(), t.attempts, t.attempts ? static_cast<double>(t.reached) / t.attempts : 0.0,
        t.others_solved, t.others_undone,
        t.others_solved ? static_cast<double>(t.others_undone) / t.others_solved : 0.0, t.independent_solved,
        t.independent_undone,
        t.independent_solved ? static_cast<double>(t.independent_undone) / t.independent_solved : 0.0);
  // ... and which of them: the share each solved object was undone (of how many), and the share
  // of all solved ones that ended beyond twice the threshold
  for (const auto& [entity, t] : tally) {
    if (t.by_object.empty()) continue;
    std::string line = "  solved objects undone by attempts on " + EntityName(entity) + ":";
    for (const auto& [other, counts] : t.by_object)
      line += " " + EntityName(other) + " " + ShareOf(counts.second, counts.first) + ",";
    std::printf("%s beyond %.2f m %.2f; undone before %s had moved %.0f cm: %s\n", line.c_str(),
                2 * eval_options.threshold, t.others_solved ? static_cast<double>(t.pushed_far) / t.others_solved : 0.0,
                EntityName(entity).c_str(), 100 * actor::EvalEpisodeObserver::Attempt::kMovedM,
                ShareOf(t.others_undone_before_moved, t.others_undone).c_str());
  }
  std::printf("wrote %s/episodes.csv and attempts.csv\n", out_dir.c_str());
  return 0;
}

}  // namespace srics::eval
