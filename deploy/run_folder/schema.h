#pragma once
// The columns of the CSV files a run folder holds, in the order they are written. Readers find
// columns by name (csv.h), so files written before a column was added still read.
//
//   eval.csv     one row per evaluation an actor reports (the monitor's CSV sink): wall_time is
//                Unix time in seconds; entity_distance and subgoal_success are ';'-joined per
//                entity; independent_solved / independent_undone are summed over the
//                evaluation's attempts (solved objects an attempt began with that are not its
//                entity's ancestors, and how many it undid; files before 2026-12-04 end at
//                subgoal_success). policy_version 0 is the passive policy, the baseline.
//   learner.csv  one row per LearnerStats sample.
//   nodes.csv    one row per NodeStatus (state is the node's own, or "lost" / "exited" when the
//                monitor saw it go).
//   episodes.csv and attempts.csv of `srics eval` (deploy/eval/eval.cc): one row per
//                evaluation episode, and per attempt of a subgoal within one.

#include <string>
#include <vector>

namespace srics::run_folder {

inline const std::vector<std::string> kEvalColumns = {
    "wall_time",   "run_id",          "actor_id",        "policy_version",      "graph_version",
    "env_steps",   "episodes",        "avg_distance",    "avg_object_distance", "success_rate",
    "selectivity", "entity_distance", "subgoal_success", "independent_solved",  "independent_undone"};

inline const std::vector<std::string> kLearnerColumns = {"wall_time",
                                                         "run_id",
                                                         "updates",
                                                         "transitions_inserted",
                                                         "replay_size",
                                                         "episodes_accepted",
                                                         "episodes_rejected",
                                                         "policy_version",
                                                         "q_loss",
                                                         "policy_loss",
                                                         "alpha",
                                                         "entropy",
                                                         "updates_per_second",
                                                         "inserts_per_second",
                                                         "mean_reward"};

inline const std::vector<std::string> kNodesColumns = {
    "wall_time",      "run_id",        "role",      "node_id",         "host",      "pid",   "state",
    "policy_version", "graph_version", "env_steps", "dropped_samples", "uptime_ms", "detail"};

// episodes.csv's first columns; then distance_<entity> per entity, subgoal_success_<entity> per
// subgoal entity and the video's file name.
inline const std::vector<std::string> kEpisodesLeadingColumns = {"episode",
                                                                 "seed",
                                                                 "status",
                                                                 "steps",
                                                                 "frames",
                                                                 "avg_distance",
                                                                 "avg_object_distance",
                                                                 "success",
                                                                 "selectivity",
                                                                 "independent_solved",
                                                                 "independent_undone"};

inline const std::vector<std::string> kAttemptsColumns = {"episode",
                                                          "attempt",
                                                          "entity",
                                                          "skipped",
                                                          "distance_before",
                                                          "distance_after",
                                                          "reached",
                                                          "others_solved",
                                                          "others_undone",
                                                          "independent_solved",
                                                          "independent_undone",
                                                          "distances_before",
                                                          "distances_after",
                                                          "others_undone_before_moved"};

}  // namespace srics::run_folder
