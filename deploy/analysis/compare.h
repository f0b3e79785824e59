#pragma once
// `srics compare DIR... [--out DIR]`: the paper's figures and a table of final figures from
// the CSV files of finished or running runs, over methods and seeds.
//
// Each DIR is a sweep folder (its run folders are the subfolders holding eval.csv) or one
// run folder. A run's method and seed come from its folder name (<method>-seed<N>, as
// `srics sweep` names them) or else from its config.yaml; its environment is the name of the
// config file of the sweep (sweep.yaml), else the run folder's parent folder name. Runs are
// grouped by environment and method.
//
// Per environment (OUT/<env>-*.png, each with its .dat and .gnuplot):
//   distance.png         average distance of all entities, arm included, vs env steps
//   object_distance.png  average object distance vs env steps
//   subgoal_success.png  per-subgoal success at each run's final evaluation (bars)
//   selectivity.png      selectivity of training episodes vs env steps (train.csv)
// Curves: the mean over seeds, the band mean ± one sample standard deviation over seeds (as the
// paper shades; --band minmax: minimum to maximum), each run interpolated linearly onto the
// group's evaluation grid (a point uses the seeds that reached it); the passive policy (policy
// version 0) as a dashed line; the legend below the plot. Bars: mean, error bars as the band.
// --methods picks the methods drawn and tabled (a panel of the methods, another of the
// ablations); --panel NAME names the files <env>-NAME-*.png and results-NAME.md so that panels
// share a folder.
//   undone.png           share of the solved non-ancestor objects an evaluation attempt undid
//                        (eval.csv's independent_* columns; runs before 2026-12-04 have none)
// OUT/results.md: per environment and method, each run's final evaluation (its last, never its
// best) summarized as mean ± sample standard deviation over seeds, with n; a second table beside
// it: the mean of each run's last five evaluations, the final undone share and, where the run
// folder has one, the final evaluation of its last checkpoint (final-eval/).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "deploy/analysis/statistics.h"

namespace srics::analysis {

struct CompareOptions {
  std::vector<std::string> dirs;
  std::string out_dir;                    // "" = DIR/compare for one DIR, ./compare for several
  std::string final_eval = "final-eval";  // subfolder of the final evaluation (FinalEvaluation)
  std::vector<std::string> methods;       // the methods drawn and tabled; empty: every method
  std::string panel;                      // "" or the files' infix: <env>-<panel>-distance.png
  enum class Band { kStd, kMinMax } band = Band::kStd;
};

// One evaluation of a run (the rows of eval.csv at one env-step count, averaged).
struct EvalPoint {
  double env_steps = 0;
  double avg_distance = 0;
  double avg_object_distance = 0;
  double success_rate = 0;
  std::vector<double> subgoal_success;
  // compatibility (eval.csv since 2026-12-04): solved objects the attempts began with that
  // are not the attempted entity's ancestors, and how many of those the attempts undid
  double independent_solved = 0, independent_undone = 0;
  bool has_compatibility = false;
};

// The final evaluation of a run's last checkpoint by `srics eval` (FINAL/episodes.csv and
// attempts.csv, FINAL the run folder's final-eval/ or another CompareOptions::final_eval; its
// passive baseline on the same goals in FINAL-passive/), when the campaign made one: more
// episodes than one in-run evaluation.
struct FinalEvaluation {
  int episodes = 0;
  double avg_distance = 0, avg_object_distance = 0;
  double passive_object_distance = -1;  // -1 without final-eval-passive/
  double independent_solved = 0, independent_undone = 0;
  // Attempts on movable objects only (not the arm, not a static object): of the other subgoal
  // entities solved when an attempt began (ancestors too: attempts.csv others_solved), how many
  // it undid. Unlike the undone share above it does not depend on the graph's ancestor sets;
  // the protocol's subgoal entities count (SMORL's random protocol includes a static object,
  // rarely solved). Empty without the run's config.yaml or when its episodes draw object sets
  // (attempts.csv's entity is then a place in the episode, not a catalogue index).
  std::optional<double> object_attempt_solved, object_attempt_undone;
};

// What compare reads of one run folder.
struct RunData {
  std::string dir;
  std::string environment;
  std::string method;
  uint64_t seed = 0;
  bool finished = false;                               // outcome.yaml says so
  std::vector<EvalPoint> evaluations;                  // trained policy, env-step order
  std::optional<EvalPoint> passive;                    // the first evaluation of policy version 0
  std::vector<std::pair<double, double>> selectivity;  // train.csv: env steps, selectivity
  std::optional<FinalEvaluation> final_evaluation;
  bool selectivity_with_table_graph = false;  // measured with the table's graph (else the episodes' own ancestor sets)
  // the run's graph.json as edges ("action->0, 0->2"), empty when it has none; the graph its
  // config.yaml implies by construction, empty when that cannot be read; graph.png if drawn;
  // the graph in graphviz's language, to draw it when the folder has no graph.png (the
  // campaign's raw folders keep only graph.json)
  std::string graph, graph_by_construction, graph_picture, graph_dot;
  // the catalogue numbers of the objects its evaluation plays, in episode order, when its
  // config.yaml names one evaluation set (env.eval_object_sets: the held-out combination);
  // empty otherwise (every object, in catalogue order)
  std::vector<int> eval_objects;
};

// Reads every run under the folders; folders it cannot use are named in *warnings.
// `final_eval`: the run folders' subfolder of the final evaluation (CompareOptions::final_eval).
std::vector<RunData> ReadRuns(const std::vector<std::string>& dirs, std::vector<std::string>* warnings,
                              const std::string& final_eval = "final-eval");

// Mean, sample standard deviation (0 for one value), minimum and maximum.

// Linear interpolation of a curve (x ascending) at x; empty outside its range.
std::optional<double> Interpolate(const std::vector<std::pair<double, double>>& curve, double x);

// The markdown table of final figures (results.md).
std::string FinalTable(const std::vector<RunData>& runs);

// Writes the figures and results.md; returns 0, or 1 when no run was found or gnuplot failed
// (the table is written anyway).
int Compare(const CompareOptions& options);

}  // namespace srics::analysis
