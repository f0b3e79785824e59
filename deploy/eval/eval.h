#pragma once
// `srics eval RUN_DIR|CHECKPOINT [--episodes N] [--out DIR] ...`: watches a trained policy.
// (With several RUN_DIRs and --cross-protocol or --seen/--unseen: a study, eval_studies.h.)
// Loads the run's effective config (config.yaml beside the checkpoint, or --config), the
// learner checkpoint's policy (HAC: both levels) and, for the methods that use one, the run's
// interaction graph (graph.json); then plays the evaluation protocol of the evaluating actors
// (actor::RunEvaluationEpisode with the run's evaluation seeds: the goals of eval.csv, the
// full goal split into subgoals in graph-depth order for SRICS) and writes to DIR:
//   episodes.csv         per episode: steps, frames, distances (average, objects, per entity),
//                        success, selectivity, per-subgoal success, the video's file
//   episode-NNN.mp4      the episode as MuJoCo renders it (headless EGL), goals drawn as
//                        translucent markers, one frame per env step plus the first state;
//                        .gif, or a folder of PNG frames (--format png, or without ffmpeg)
//   attempts.csv         per subgoal attempt: skipped or not, distance before and after, the
//                        objects solved before it that it left unsolved
// --protocol and --goal-set play a policy under another method's protocol on other goals.
// Exit codes: 0 done, 1 a run folder without checkpoint or graph, a corrupt checkpoint, no
// renderer, ffmpeg failing; 2 bad arguments or config (the message names the argument).

#include <string>
#include <vector>

#include "actor/env/render/episode_renderer.h"
#include "actor/env/render/video_writer.h"

namespace srics::eval {

struct EvalArgs {
  std::string target;                  // RUN_DIR or CHECKPOINT (the first of targets)
  std::vector<std::string> targets;    // several RUN_DIRs: a study (eval_studies.h)
  int episodes = -1;                   // --episodes (-1: actors.eval_episodes of the config)
  std::string out_dir;                 // --out ("" = <run folder>/eval)
  std::string config_file;             // --config ("" = config.yaml beside the checkpoint)
  std::string graph_file;              // --graph ("" = graph.json beside the checkpoint)
  std::vector<std::string> overrides;  // --set key.path=value (on top of the run's config)
  bool video = true;                   // --no-video: metrics only
  std::string format;                  // --format mp4|gif|png ("" = mp4 with ffmpeg, else png)
  env::RenderOptions render;           // --width, --height
  int fps = 10;                        // --fps (10 = real time: an env step is 0.1 s)
  // --protocol: "" = the method's own; "depth": the subgoals of an interaction graph (the run's,
  // --graph, or for methods without one the table's graph by construction) in depth order, as
  // SRICS evaluates; "random": every entity a subgoal, in random order, as SMORL evaluates.
  // Plays any subgoal policy under either protocol (not the full-goal methods).
  std::string protocol;
  // --goal-set S: the evaluation goals of a run with seed S (0 = the run's own seed), so that
  // policies of different seeds are compared on the same goals
  uint64_t goal_set = 0;
  // --passive: the passive baseline (the hand never moves) on the same goals instead of the
  // checkpoint's policy, which is then not needed: what the run's eval.csv divides by, for
  // goals or objects (--set env.eval_object_sets=...) the run never evaluated
  bool passive = false;
  // The studies over several runs (eval_studies.h): --cross-protocol on the goals of each of
  // --goal-sets (default 1,2,3; episodes default 20); --seen and --unseen (either starts the
  // study; the other defaults to rearrange-4-unseen's "1,2,3 1,2,4 1,3,4" or 2,3,4), catalogue
  // ids of the present pucks (episodes default 50). Both studies need --out.
  bool cross_protocol = false;
  std::vector<uint64_t> goal_sets;
  std::string seen, unseen;
};

// Runs the evaluation; returns 0. Throws std::invalid_argument (bad arguments: exit 2),
// config::ConfigError (exit 2), nn::CheckpointError and std::runtime_error (exit 1).
int Eval(const EvalArgs& args);

}  // namespace srics::eval
