#pragma once
// The tables of two evaluation studies of trained policies (`srics eval --cross-protocol` and
// `srics eval --seen ... --unseen ...`, deploy/eval/eval_studies.h plays the episodes):
// each evaluation's episodes.csv and attempts.csv summed into one CSV row, and the CSV into a
// markdown table. Pure file and table logic: no MuJoCo, no DDS.

#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace srics::analysis {

// Cross-protocol: one run's final policy under one protocol ("depth" or "random") on the goals
// of one evaluation seed.
inline constexpr const char* kCrossEvalHeader =
    "run,method,protocol,goal_set,episodes,avg_distance,avg_object_distance,object_attempts,object_reached,"
    "objects_solved_before,objects_undone";

// The CSV row (without '\n') of one evaluation folder (its episodes.csv and attempts.csv):
// the means over the stable episodes, and over the attempts that were not skipped on the
// entities in `objects` (those with a subgoal under the depth protocol, the arm not): how many,
// the share that reached their goal, the solved objects they began with and how many they undid.
std::string CrossEvalRow(const std::string& run, const std::string& method, const std::string& protocol,
                         uint64_t goal_set, const std::filesystem::path& eval_dir, const std::set<int>& objects);

// The entities other than the arm (0) that a depth-protocol evaluation attempted (attempts.csv).
std::set<int> AttemptedObjects(const std::filesystem::path& depth_eval_dir);

// The markdown of cross-eval.csv's text: per run and protocol the means over goal sets; per method
// and protocol mean ± sd over its runs. Throws std::invalid_argument for a CSV without its columns.
std::string CrossEvalTable(const std::string& csv, const std::string& goal_sets, int episodes);

// Seen and unseen object combinations: one run's final policy and the passive baseline on one
// combination of catalogue objects.
inline constexpr const char* kSeenUnseenHeader =
    "run,combination,kind,episodes,object_distance,passive_episodes,passive_object_distance,ratio";

// "n,mean" of the stable episodes' avg_object_distance in an episodes.csv ("0," without any).
std::string ObjectDistanceOf(const std::filesystem::path& episodes_csv);

// The CSV row (without '\n'): `combination` as ids joined by spaces, kind "seen" or "unseen".
std::string SeenUnseenRow(const std::string& run, const std::string& combination, const std::string& kind,
                          const std::filesystem::path& policy_episodes, const std::filesystem::path& passive_episodes);

// The markdown of seen-unseen.csv's text: every row, then per run the mean ratio over the seen
// combinations and the unseen one, and over runs mean ± sd of both and of their paired difference.
std::string SeenUnseenTable(const std::string& csv, const std::string& seen, const std::string& unseen, int episodes);

}  // namespace srics::analysis
