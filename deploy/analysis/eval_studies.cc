#include "deploy/analysis/eval_studies.h"

#include <cstdio>
#include <map>
#include <stdexcept>

#include "deploy/analysis/statistics.h"
#include "deploy/run_folder/csv.h"

namespace srics::analysis {
namespace {

namespace fs = std::filesystem;

// An attempts.csv entity index, or nothing when the field is not a small whole number.
std::optional<int> EntityOf(const run_folder::CsvRow& row) {
  const std::optional<double> entity = row.Number("entity");
  if (!entity || *entity < 0 || *entity > 1e6 || *entity != static_cast<double>(static_cast<int>(*entity)))
    return std::nullopt;
  return static_cast<int>(*entity);
}

run_folder::CsvTable ParseOrThrow(const std::string& csv, const char* header, const char* what) {
  std::optional<run_folder::CsvTable> table = run_folder::CsvTable::Parse(csv);
  if (!table) throw std::invalid_argument(std::string(what) + ": empty");
  const std::optional<run_folder::CsvTable> expected = run_folder::CsvTable::Parse(std::string(header) + "\n");
  for (const std::string& column : expected->header())
    if (!table->HasColumn(column)) throw std::invalid_argument(std::string(what) + ": no column " + column);
  return std::move(*table);
}

}  // namespace

std::set<int> AttemptedObjects(const fs::path& depth_eval_dir) {
  std::set<int> objects;
  if (const auto attempts = run_folder::CsvTable::Read(depth_eval_dir / "attempts.csv"))
    for (const run_folder::CsvRow& row : attempts->Rows())
      if (const std::optional<int> entity = EntityOf(row); entity && *entity != 0) objects.insert(*entity);
  return objects;
}

std::string CrossEvalRow(const std::string& run, const std::string& method, const std::string& protocol,
                         uint64_t goal_set, const fs::path& eval_dir, const std::set<int>& objects) {
  int episodes = 0;
  double distance = 0, object_distance = 0;
  if (const auto table = run_folder::CsvTable::Read(eval_dir / "episodes.csv"))
    for (const run_folder::CsvRow& row : table->Rows()) {
      if (row.Text("status") != "ok") continue;
      ++episodes;
      distance += row.Number("avg_distance").value_or(0);
      object_distance += row.Number("avg_object_distance").value_or(0);
    }
  int attempts = 0;
  double reached = 0, solved = 0, undone = 0;
  if (const auto table = run_folder::CsvTable::Read(eval_dir / "attempts.csv"))
    for (const run_folder::CsvRow& row : table->Rows()) {
      const std::optional<int> entity = EntityOf(row);
      if (row.Text("skipped") != "0" || !entity || !objects.count(*entity)) continue;
      ++attempts;
      reached += row.Number("reached").value_or(0);
      solved += row.Number("others_solved").value_or(0);
      undone += row.Number("others_undone").value_or(0);
    }
  std::string line =
      run + "," + method + "," + protocol + "," + std::to_string(goal_set) + "," + std::to_string(episodes) + ",";
  line += episodes ? Format(distance / episodes, 5) + "," + Format(object_distance / episodes, 5) : ",";
  line += "," + std::to_string(attempts) + "," + Format(attempts ? reached / attempts : 0, 4) + "," +
          Format(solved, 0) + "," + Format(undone, 0);
  return line;
}

std::string CrossEvalTable(const std::string& csv, const std::string& goal_sets, int episodes) {
  const run_folder::CsvTable table = ParseOrThrow(csv, kCrossEvalHeader, "cross-eval.csv");
  struct Sums {
    double distance = 0, object = 0, attempts = 0, reached = 0, solved = 0, undone = 0;
    int goal_sets = 0;
  };
  std::vector<std::string> runs;                 // in order of first appearance
  std::map<std::string, std::string> method_of;  // run -> method
  std::map<std::pair<std::string, std::string>, Sums> sums;
  for (const run_folder::CsvRow& row : table.Rows()) {
    const std::string run = row.Text("run");
    if (!method_of.count(run)) runs.push_back(run);
    method_of[run] = row.Text("method");
    Sums& s = sums[{run, row.Text("protocol")}];
    const double attempts = row.Number("object_attempts").value_or(0);
    s.distance += row.Number("avg_distance").value_or(0);
    s.object += row.Number("avg_object_distance").value_or(0);
    s.attempts += attempts;
    s.reached += row.Number("object_reached").value_or(0) * attempts;
    s.solved += row.Number("objects_solved_before").value_or(0);
    s.undone += row.Number("objects_undone").value_or(0);
    ++s.goal_sets;
  }
  std::string out =
      "# Cross-evaluation: each final policy under both protocols, on the same goals\n\n"
      "Goals of evaluation seeds " +
      goal_sets + ", " + std::to_string(episodes) +
      " episodes each; distances in metres at the final step. depth: the graph's subgoals in depth order (the arm "
      "last; runs without a graph use the table's graph by construction); random: every entity a subgoal (static "
      "ones too), random order. reached: object attempts ending within 0.05 m of their goal; undone: objects solved "
      "before an attempt that it left unsolved. Written by srics eval --cross-protocol.\n\n"
      "| run | method | protocol | avg distance (arm incl.) | avg object distance | object attempts reached | "
      "solved objects undone |\n|---|---|---|---|---|---|---|\n";
  std::vector<std::pair<std::string, std::string>> method_order;  // (method, protocol), first appearance
  std::map<std::pair<std::string, std::string>, std::vector<double>> method_distance, method_object;
  for (const std::string& run : runs)
    for (const char* protocol : {"depth", "random"}) {
      const auto it = sums.find({run, protocol});
      if (it == sums.end()) continue;
      const Sums& s = it->second;
      const double distance = s.distance / s.goal_sets, object = s.object / s.goal_sets;
      out += "| " + run + " | " + method_of[run] + " | " + protocol + " | " + Format(distance) + " | " +
             Format(object) + " | " + Format(s.attempts ? s.reached / s.attempts : 0, 2) + " | " +
             Format(s.solved ? s.undone / s.solved : 0, 2) + " |\n";
      const std::pair<std::string, std::string> key{method_of[run], protocol};
      if (!method_distance.count(key)) method_order.push_back(key);
      method_distance[key].push_back(distance);
      method_object[key].push_back(object);
    }
  out += "\n| method | protocol | runs | avg distance (arm incl.) | avg object distance |\n|---|---|---|---|---|\n";
  for (const auto& key : method_order) {
    const Spread d = SpreadOf(method_distance[key]), o = SpreadOf(method_object[key]);
    out += "| " + key.first + " | " + key.second + " | " + std::to_string(d.n) + " | " + MeanStd(d) + " | " +
           MeanStd(o) + " |\n";
  }
  return out;
}

std::string ObjectDistanceOf(const fs::path& episodes_csv) {
  int n = 0;
  double sum = 0;
  if (const auto table = run_folder::CsvTable::Read(episodes_csv))
    for (const run_folder::CsvRow& row : table->Rows())
      if (row.Text("status") == "ok") ++n, sum += row.Number("avg_object_distance").value_or(0);
  return std::to_string(n) + "," + (n ? Format(sum / n, 5) : "");
}

std::string SeenUnseenRow(const std::string& run, const std::string& combination, const std::string& kind,
                          const fs::path& policy_episodes, const fs::path& passive_episodes) {
  const std::string policy = ObjectDistanceOf(policy_episodes), passive = ObjectDistanceOf(passive_episodes);
  const std::string a = policy.substr(policy.find(',') + 1), b = passive.substr(passive.find(',') + 1);
  // the ratio of the two means as the CSV holds them (5 decimals), so the table can be made again from it
  const std::string ratio = !a.empty() && !b.empty() && std::stod(b) > 0 ? Format(std::stod(a) / std::stod(b), 4) : "";
  return run + "," + combination + "," + kind + "," + policy + "," + passive + "," + ratio;
}

std::string SeenUnseenTable(const std::string& csv, const std::string& seen, const std::string& unseen, int episodes) {
  const run_folder::CsvTable table = ParseOrThrow(csv, kSeenUnseenHeader, "seen-unseen.csv");
  std::string out =
      "# Seen and unseen object combinations: final object distance over the passive baseline\n\n"
      "Each run's final policy and the passive baseline (the hand never moves) on the run's evaluation goals, " +
      std::to_string(episodes) +
      " episodes per combination; combinations are the catalogue ids of the present pucks (seen: " + seen +
      "; unseen: " + unseen +
      "). Lower is better, 1 is the passive level. Written by srics eval --seen ... --unseen ....\n\n"
      "| run | objects | kind | object distance | passive | ratio |\n|---|---|---|---|---|---|\n";
  std::vector<std::string> runs;
  std::map<std::string, std::vector<double>> seen_ratios;
  std::map<std::string, double> unseen_ratio;
  for (const run_folder::CsvRow& row : table.Rows()) {
    const std::string run = row.Text("run");
    if (!seen_ratios.count(run) && !unseen_ratio.count(run)) runs.push_back(run);
    const double ratio = row.Number("ratio").value_or(0);
    if (row.Text("kind") == "seen")
      seen_ratios[run].push_back(ratio);
    else
      unseen_ratio[run] = ratio;
    out += "| " + run + " | " + row.Text("combination") + " | " + row.Text("kind") + " | " +
           Format(row.Number("object_distance").value_or(0), 4) + " | " +
           Format(row.Number("passive_object_distance").value_or(0), 4) + " | " + Format(ratio) + " |\n";
  }
  out += "\n| run | seen (mean over combinations) | unseen | unseen - seen |\n|---|---|---|---|\n";
  std::vector<double> seen_means, unseen_values;
  for (const std::string& run : runs) {
    seen_means.push_back(SpreadOf(seen_ratios[run]).mean);
    unseen_values.push_back(unseen_ratio[run]);
    out += "| " + run + " | " + Format(seen_means.back()) + " | " + Format(unseen_values.back()) + " | " +
           Format(unseen_values.back() - seen_means.back(), 3, /*sign=*/true) + " |\n";
  }
  out += "| mean ± sd over " + std::to_string(runs.size()) + " runs | " + MeanStd(SpreadOf(seen_means)) + " | " +
         MeanStd(SpreadOf(unseen_values)) + " | " +
         MeanStd(SpreadOf(Differences(seen_means, unseen_values)), 3, /*sign=*/true) + " |\n";
  return out;
}

}  // namespace srics::analysis
