#include "deploy/analysis/gnuplot.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "common/files/shell_path.h"
#include "deploy/run_folder/csv.h"

namespace srics::analysis {

std::string GnuplotQuote(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out;
}

namespace {

// eval.csv as curves: the trained policy's evaluations in env-step order and the first
// evaluation of the passive policy (version 0), when there is one.
struct EvalCurve {
  struct Point {
    double steps, distance, object_distance;
    std::vector<double> success;
  };
  std::vector<Point> points;
  bool have_passive = false;
  double passive_distance = 0, passive_object = 0;
  size_t entities = 0;  // the longest per-subgoal success list
};

EvalCurve ReadEvalCurve(const run_folder::CsvTable& eval) {
  EvalCurve curve;
  for (const run_folder::CsvRow& row : eval.Rows()) {
    const auto version = row.Number("policy_version"), steps = row.Number("env_steps");
    const auto distance = row.Number("avg_distance"), object = row.Number("avg_object_distance");
    if (!version || !steps || !distance || !object) continue;
    if (*version == 0) {
      if (!curve.have_passive)
        curve.passive_distance = *distance, curve.passive_object = *object, curve.have_passive = true;
      continue;
    }
    curve.points.push_back({*steps, *distance, *object, run_folder::SplitValues(row.Text("subgoal_success"))});
  }
  std::stable_sort(curve.points.begin(), curve.points.end(),
                   [](const EvalCurve::Point& a, const EvalCurve::Point& b) { return a.steps < b.steps; });
  for (const EvalCurve::Point& p : curve.points) curve.entities = std::max(curve.entities, p.success.size());
  return curve;
}

// curve.dat: one row per evaluation (env steps, distances, per-subgoal success).
void WriteCurveData(const std::string& dir, const EvalCurve& curve) {
  std::ofstream data(dir + "/curve.dat");
  data << "# env_steps avg_distance avg_object_distance subgoal_success_0..N-1\n";
  for (const EvalCurve::Point& p : curve.points) {
    data << p.steps << ' ' << p.distance << ' ' << p.object_distance;
    for (size_t i = 0; i < curve.entities; ++i) data << ' ' << (i < p.success.size() ? p.success[i] : 0.0);
    data << '\n';
  }
}

// The gnuplot script of curve.png (distances, with the passive policy's as flat lines) and
// subgoal_success.png.
void WriteGnuplotScript(const std::string& path, const std::string& dir, const std::string& title,
                        const EvalCurve& curve) {
  std::ofstream script(path);
  script << "set terminal pngcairo size 900,540 font 'sans,10'\n"
         << "set output 'curve.png'\n"
         << "set title '" << GnuplotQuote(title) << "' noenhanced\n"
         << "set xlabel 'environment steps'\nset ylabel 'final distance to goal (m)'\n"
         << "set key outside right top\nset grid\nset yrange [0:*]\n";
  std::string plot =
      "plot 'curve.dat' using 1:3 with linespoints lw 2 title 'avg object distance', "
      "'' using 1:2 with linespoints lw 2 title 'avg distance (arm incl.)'";
  if (curve.have_passive) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer,
                  ", %.9g with lines dt 2 lw 2 title 'passive: avg object distance', %.9g with lines dt 3 lw 2 "
                  "title 'passive: avg distance'",
                  curve.passive_object, curve.passive_distance);
    plot += buffer;
  }
  script << plot << "\n";
  if (curve.entities > 0) {
    script << "set output 'subgoal_success.png'\n"
           << "set title 'per-subgoal success: " << GnuplotQuote(title) << "' noenhanced\n"
           << "set ylabel 'success rate'\nset yrange [0:1.05]\nplot ";
    for (size_t i = 0; i < curve.entities; ++i)
      script << (i ? ", " : "") << "'curve.dat' using 1:" << 4 + i << " with linespoints lw 2 title 'entity " << i
             << "'";
    script << "\n";
  }
}

}  // namespace

bool RunGnuplot(const std::string& script_path, std::string* error) {
  // in the script's folder: scripts name their files relative to it, so a folder of them (a
  // committed `srics compare` output) regenerates byte for byte wherever it is checked out
  const std::filesystem::path script(script_path);
  const std::string folder = script.has_parent_path() ? script.parent_path().string() : ".";
  const std::string command =
      "cd " + files::ShellQuote(folder) + " && gnuplot " + files::ShellQuote(script.filename().string()) + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) {
    *error = "cannot run gnuplot";
    return false;
  }
  char buffer[512];
  std::string output;
  while (fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  if (status != 0) {
    *error = "gnuplot failed (status " + std::to_string(status) + "): " + output;
    return false;
  }
  return true;
}

bool PlotEvalCurves(const std::string& dir, const std::string& title, std::string* error) {
  const std::optional<run_folder::CsvTable> eval = run_folder::CsvTable::Read(dir + "/eval.csv");
  if (!eval) {
    *error = "no eval.csv";
    return false;
  }
  const EvalCurve curve = ReadEvalCurve(*eval);
  if (curve.points.empty()) {
    *error = "no evaluation of a trained policy in eval.csv";
    return false;
  }
  WriteCurveData(dir, curve);
  const std::string script_path = dir + "/curve.gnuplot";
  WriteGnuplotScript(script_path, dir, title, curve);
  return RunGnuplot(script_path, error);
}

}  // namespace srics::analysis
