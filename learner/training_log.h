#pragma once
// What the training episodes the learner takes in looked like, per window of training env
// steps: the paper plots selectivity during training, and only the learner sees every
// training episode. Rows go to <run folder>/train.csv (one per window, appended, flushed):
//
//   wall_time,env_steps,episodes,selectivity,selectivity_episodes,subgoal_distance,subgoal_success,
//   table_graph_selectivity,table_graph_selectivity_episodes
//
// env_steps: the learner's training env steps when the row was written (the window's end);
// episodes: training episodes with a subgoal entity in the window; selectivity: the mean over
// those episodes of each episode's mean per-step selectivity measure (rl::SelectivityMeasure,
// the evaluation's measure, with the episode's own ancestor set), over the episodes where it
// is defined (selectivity_episodes); subgoal_distance and subgoal_success: the subgoal
// entity's final distance to its goal and the share of episodes ending within the success
// threshold. Episodes without a subgoal entity (exploration, full-goal methods) are not
// counted; a window without any writes no row. A tied pair attempted as one counts as one episode:
// its farther object's distance, the pair's selectivity. table_graph_selectivity: the same measure with
// the ancestor sets of the table's graph by construction (options.table_graph), the same for
// every method, so that methods compare (SMORL's own ancestor sets are empty: its selectivity
// counts the arm that pushes as an independent mover); empty without a table graph. Rows of
// files written before those two columns existed are kept with them empty.

#include <cstdint>
#include <fstream>
#include <optional>
#include <string>

#include "common/rl/episode.h"
#include "common/rl/graph.h"

namespace srics::learner {

struct TrainingLogOptions {
  std::string path;                 // "" = no log
  uint64_t every_env_steps = 5000;  // the window (the run's evaluation interval)
  double epsilon = 1e-5;            // below it nothing moved: selectivity undefined for the step
  double success_threshold = 0.05;  // m
  // the table's graph by construction (rl::GroundTruthGraph), over the catalogue; measured
  // against only, never used for training
  std::optional<rl::InteractionGraph> table_graph;
};

class TrainingLog {
 public:
  explicit TrainingLog(TrainingLogOptions options);

  // After a restart from a checkpoint at `env_steps` training env steps: rows written after
  // that checkpoint (beyond env_steps) are dropped, since the resumed run trains those steps
  // again, and windows continue from there. Throws std::runtime_error when the file cannot
  // be rewritten.
  void ResumeAt(uint64_t env_steps);
  // What the log keeps of one training episode: empty for episodes it does not count.
  struct Figures {
    double selectivity = -1;  // negative: undefined (nothing moved)
    double subgoal_distance = 0;
    double table_graph_selectivity = -1;  // negative: undefined or no table graph
  };
  // partner: the object attempted together with the subgoal entity (a tied pair, graph.
  // object_ties: joint; the run's graph names it), -1 for none. A pair's episode carries both
  // goals; its distance is the farther object's, its selectivity the pair's.
  std::optional<Figures> Measure(const rl::Episode& episode, int partner = -1) const;
  // Folds in the figures of one episode the learner stored.
  void Add(const Figures& figures);
  // Writes the window's row once `env_steps` has reached its end (force: now, if it holds
  // any episode: the end of the run).
  void Advance(uint64_t env_steps, bool force = false);

  // The current window's figures (for tests).
  uint64_t episodes() const { return episodes_; }
  double mean_selectivity() const { return selectivity_episodes_ ? selectivity_sum_ / selectivity_episodes_ : 0; }

 private:
  void Open();
  void ClearWindow();  // the window's sums back to zero

  TrainingLogOptions options_;
  std::ofstream out_;
  uint64_t next_row_at_ = 0;
  uint64_t episodes_ = 0, selectivity_episodes_ = 0, successes_ = 0, table_graph_episodes_ = 0;
  double selectivity_sum_ = 0, distance_sum_ = 0, table_graph_sum_ = 0;
};

// The mean per-step selectivity measure of an episode for its subgoal entity with
// `ancestor_mask` (the episode's own by default); negative when the episode has no subgoal
// entity or nothing moved in any step.
double EpisodeSelectivity(const rl::Episode& episode, double epsilon);
// (subgoal: the episode's subgoal entity, with its tied partner when attempted as one)
double EpisodeSelectivity(const rl::Episode& episode, double epsilon, uint64_t ancestor_mask,
                          const rl::SubgoalUnit& subgoal);

}  // namespace srics::learner
