#include "deploy/analysis/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <numeric>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/config/config.h"
#include "common/files/small_file.h"
#include "common/graph_file/graph_file.h"
#include "common/rl/graph.h"
#include "common/rl/ground_truth.h"
#include "deploy/analysis/gnuplot.h"
#include "deploy/run_folder/csv.h"
#include "deploy/run_folder/outcome.h"

namespace srics::analysis {

namespace fs = std::filesystem;

namespace {

// The stem of the config file a sweep folder's sweep.yaml names ("relational-4").
std::optional<std::string> SweepEnvironment(const fs::path& sweep_dir) {
  if (!fs::exists(sweep_dir / "sweep.yaml")) return std::nullopt;
  std::istringstream in(files::ReadSmallFile((sweep_dir / "sweep.yaml").string()));  // throws over the size limit
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("config: ", 0) != 0) continue;
    std::string path = line.substr(8);
    if (path.size() >= 2 && path.front() == '"') path = path.substr(1, path.size() - 2);
    return fs::path(path).stem().string();
  }
  return std::nullopt;
}

// run.method and run.seed from an effective config.yaml (the `run:` block).
bool MethodAndSeedFromConfig(const fs::path& path, std::string* method, uint64_t* seed) {
  std::ifstream in(path);
  bool in_run = false, have_method = false;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (line[0] != ' ') {
      in_run = line.rfind("run:", 0) == 0;
      continue;
    }
    if (!in_run) continue;
    const size_t start = line.find_first_not_of(' ');
    const std::string entry = line.substr(start);
    if (start != 2) continue;  // only the block's own keys
    if (entry.rfind("method: ", 0) == 0) *method = entry.substr(8), have_method = true;
    if (entry.rfind("seed: ", 0) == 0) *seed = std::strtoull(entry.c_str() + 6, nullptr, 10);
  }
  return have_method;
}

// Means over the good episodes of a `srics eval` episodes.csv; none without the file, n = 0
// when no episode is good.
struct EpisodeMeans {
  int n = 0;
  double distance = 0, object_distance = 0;
};
std::optional<EpisodeMeans> ReadEpisodeMeans(const fs::path& path) {
  const std::optional<run_folder::CsvTable> episodes = run_folder::CsvTable::Read(path);
  if (!episodes) return std::nullopt;
  EpisodeMeans means;
  for (const run_folder::CsvRow& row : episodes->Rows()) {
    const auto distance = row.Number("avg_distance"), object = row.Number("avg_object_distance");
    if (!distance || !object || row.Text("status") != "ok") continue;
    means.distance += *distance, means.object_distance += *object, ++means.n;
  }
  if (means.n > 0) means.distance /= means.n, means.object_distance /= means.n;
  return means;
}

// NAME/ (and NAME-passive/) of a run folder, when present and readable.
// `movable[e]`: entity e of the evaluation episodes is an object the arm can move (empty: not known).
std::optional<FinalEvaluation> ReadFinalEvaluation(const fs::path& dir, const std::string& name,
                                                   const std::vector<bool>& movable,
                                                   std::vector<std::string>* warnings) {
  const std::optional<EpisodeMeans> means = ReadEpisodeMeans(dir / name / "episodes.csv");
  if (!means) return std::nullopt;
  if (means->n == 0) {
    warnings->push_back((dir / name).string() + ": no episode in episodes.csv: skipped");
    return std::nullopt;
  }
  FinalEvaluation f;
  f.episodes = means->n;
  f.avg_distance = means->distance;
  f.avg_object_distance = means->object_distance;
  if (const std::optional<run_folder::CsvTable> attempts = run_folder::CsvTable::Read(dir / name / "attempts.csv"))
    for (const run_folder::CsvRow& row : attempts->Rows()) {
      if (row.Text("skipped") == "1") continue;  // no steps, nothing undone
      f.independent_solved += row.Number("independent_solved").value_or(0);
      f.independent_undone += row.Number("independent_undone").value_or(0);
      const std::optional<double> entity = row.Number("entity");
      if (movable.empty() || !entity || *entity < 0 || *entity >= static_cast<double>(movable.size()) ||
          !movable[static_cast<size_t>(*entity)])
        continue;
      f.object_attempt_solved = f.object_attempt_solved.value_or(0) + row.Number("others_solved").value_or(0);
      f.object_attempt_undone = f.object_attempt_undone.value_or(0) + row.Number("others_undone").value_or(0);
    }
  const std::optional<EpisodeMeans> passive = ReadEpisodeMeans(dir / (name + "-passive") / "episodes.csv");
  if (passive && passive->n > 0) f.passive_object_distance = passive->object_distance;
  return f;
}

std::optional<RunData> ReadRun(const fs::path& dir, const std::string& environment, const std::string& final_eval,
                               std::vector<std::string>* warnings) {
  RunData run;
  run.dir = dir.string();
  run.environment = environment;
  static const std::regex kName("(.+)-seed([0-9]+)");
  std::smatch m;
  const std::string name = dir.filename().string();
  if (std::regex_match(name, m, kName)) {
    run.method = m[1];
    run.seed = std::strtoull(m[2].str().c_str(), nullptr, 10);
  } else if (!MethodAndSeedFromConfig(dir / "config.yaml", &run.method, &run.seed)) {
    warnings->push_back(dir.string() + ": neither <method>-seed<N> nor a config.yaml naming run.method: skipped");
    return std::nullopt;
  }
  run.finished = run_folder::RunFinished(dir.string());
  std::optional<config::Config> config;
  if (fs::is_regular_file(dir / "config.yaml")) {
    try {
      config = config::LoadConfig((dir / "config.yaml").string());
    } catch (const std::exception&) {
      // a config from another version: the curves and the learned graph are still read
    }
  }
  if (config && config->env.eval_object_sets.size() == 1) run.eval_objects = config->env.eval_object_sets.front();
  const std::optional<run_folder::CsvTable> eval = run_folder::CsvTable::Read(dir / "eval.csv");
  if (!eval || !eval->HasColumn("env_steps") || !eval->HasColumn("avg_distance")) {
    warnings->push_back(dir.string() + ": no readable eval.csv (columns env_steps, avg_distance): skipped");
    return std::nullopt;
  }
  // rows at the same env-step count (several evaluators, a resumed run) are averaged
  std::map<double, std::pair<EvalPoint, int>> by_steps;
  for (const run_folder::CsvRow& row : eval->Rows()) {
    const auto steps = row.Number("env_steps");
    const auto distance = row.Number("avg_distance");
    if (!steps || !distance) continue;
    EvalPoint p;
    p.env_steps = *steps;
    p.avg_distance = *distance;
    p.avg_object_distance = row.Number("avg_object_distance").value_or(0);
    p.success_rate = row.Number("success_rate").value_or(0);
    p.subgoal_success = run_folder::SplitValues(row.Text("subgoal_success"));
    const auto solved = row.Number("independent_solved"), undone = row.Number("independent_undone");
    if (solved && undone) p.independent_solved = *solved, p.independent_undone = *undone, p.has_compatibility = true;
    if (row.Number("policy_version").value_or(1) == 0) {
      if (!run.passive) run.passive = p;
      continue;
    }
    auto& [sum, count] = by_steps[*steps];
    sum.env_steps = *steps;
    sum.avg_distance += p.avg_distance;
    sum.avg_object_distance += p.avg_object_distance;
    sum.success_rate += p.success_rate;
    sum.subgoal_success.resize(std::max(sum.subgoal_success.size(), p.subgoal_success.size()), 0.0);
    for (size_t i = 0; i < p.subgoal_success.size(); ++i) sum.subgoal_success[i] += p.subgoal_success[i];
    // counts pool over evaluators (not averaged): the share is undone / solved
    sum.independent_solved += p.independent_solved;
    sum.independent_undone += p.independent_undone;
    sum.has_compatibility |= p.has_compatibility;
    ++count;
  }
  for (auto& [steps, entry] : by_steps) {
    auto& [p, count] = entry;
    p.avg_distance /= count;
    p.avg_object_distance /= count;
    p.success_rate /= count;
    for (double& s : p.subgoal_success) s /= count;
    run.evaluations.push_back(p);
  }
  // the objects the arm can move: depth 2 or more in the table's graph (a static object has no path)
  std::vector<bool> movable;
  if (config && config->env.object_sets.empty() && config->env.eval_object_sets.empty()) {
    const rl::InteractionGraph truth = rl::GroundTruthGraph(config->env);
    const rl::SubgoalStructure structure = rl::ComputeSubgoalStructure(truth);
    for (int e = 0; e < structure.num_entities(); ++e)
      movable.push_back(e != truth.action_entity && structure.has_subgoal(e));
  }
  run.final_evaluation = ReadFinalEvaluation(dir, final_eval, movable, warnings);
  if (fs::is_regular_file(dir / "graph.json")) {
    try {
      const graph_file::LearnedGraph learned = graph_file::LoadGraph((dir / "graph.json").string());
      run.graph = rl::DescribeGraph(learned.graph);
      run.graph_dot = graph_file::GraphDot(learned);
    } catch (const std::exception& e) {
      warnings->push_back(dir.string() + ": graph.json: " + e.what());
    }
    if (config) run.graph_by_construction = rl::DescribeGraph(rl::GroundTruthGraph(config->env));
    if (fs::is_regular_file(dir / "graph.png")) run.graph_picture = (dir / "graph.png").string();
  }
  if (const std::optional<run_folder::CsvTable> train = run_folder::CsvTable::Read(dir / "train.csv")) {
    // measured with the table's graph where the run has it (the same ancestor sets for every
    // method); else with each episode's own (SMORL's: none, so the pushing arm counts against it)
    bool table_graph = false;
    for (const run_folder::CsvRow& row : train->Rows())
      table_graph |= row.Number("table_graph_selectivity").has_value();
    const std::string column = table_graph ? "table_graph_selectivity" : "selectivity";
    run.selectivity_with_table_graph = table_graph;
    std::map<double, double> by_steps_selectivity;
    for (const run_folder::CsvRow& row : train->Rows()) {
      const auto steps = row.Number("env_steps");
      const auto selectivity = row.Number(column);
      if (!steps || !selectivity || row.Number(column + "_episodes").value_or(1) <= 0) continue;
      by_steps_selectivity[*steps] = *selectivity;  // the last row of a step count wins
    }
    run.selectivity.assign(by_steps_selectivity.begin(), by_steps_selectivity.end());
  }
  return run;
}

bool HasEval(const fs::path& dir) { return fs::is_regular_file(dir / "eval.csv"); }

// The environment of runs in `sweep_dir`: its sweep.yaml's config, else the folder's name.
std::string EnvironmentOf(const fs::path& sweep_dir) {
  if (auto env = SweepEnvironment(sweep_dir)) return *env;
  const std::string name = fs::absolute(sweep_dir).lexically_normal().filename().string();
  return name.empty() ? "runs" : name;
}

}  // namespace

std::vector<RunData> ReadRuns(const std::vector<std::string>& dirs, std::vector<std::string>* warnings,
                              const std::string& final_eval) {
  std::vector<RunData> runs;
  for (const std::string& d : dirs) {
    const fs::path dir = fs::absolute(d).lexically_normal();
    if (!fs::is_directory(dir)) {
      warnings->push_back(d + ": not a folder");
      continue;
    }
    std::vector<std::pair<fs::path, std::string>> run_dirs;
    if (HasEval(dir)) {
      run_dirs.emplace_back(dir, EnvironmentOf(dir.parent_path()));
    } else {
      const std::string environment = EnvironmentOf(dir);
      for (const auto& entry : fs::directory_iterator(dir))
        if (entry.is_directory() && HasEval(entry.path())) run_dirs.emplace_back(entry.path(), environment);
      std::sort(run_dirs.begin(), run_dirs.end());
      if (run_dirs.empty()) warnings->push_back(d + ": no run folder (a subfolder with eval.csv) in it");
    }
    for (const auto& [run_dir, environment] : run_dirs)
      if (auto run = ReadRun(run_dir, environment, final_eval, warnings)) runs.push_back(std::move(*run));
  }
  // the two selectivity measures never mix within a method: where some of its runs measured
  // with the table's graph, only theirs count
  std::set<std::pair<std::string, std::string>> with_table_graph;
  for (const RunData& r : runs)
    if (r.selectivity_with_table_graph) with_table_graph.emplace(r.environment, r.method);
  for (RunData& r : runs)
    if (!r.selectivity_with_table_graph && with_table_graph.count({r.environment, r.method})) r.selectivity.clear();
  return runs;
}

std::optional<double> Interpolate(const std::vector<std::pair<double, double>>& curve, double x) {
  if (curve.empty() || x < curve.front().first || x > curve.back().first) return std::nullopt;
  const auto upper = std::lower_bound(curve.begin(), curve.end(), x,
                                      [](const std::pair<double, double>& p, double v) { return p.first < v; });
  if (upper->first == x || upper == curve.begin()) return upper->second;
  const auto lower = upper - 1;
  const double w = (x - lower->first) / (upper->first - lower->first);
  return lower->second + w * (upper->second - lower->second);
}

namespace {

using Group = std::vector<const RunData*>;
// environment -> method -> runs (seed order)
using Groups = std::map<std::string, std::map<std::string, Group>>;

// Whether a run draws in a figure: evaluations (distance figures) or selectivity rows.
using HasData = bool (*)(const RunData&);
bool HasEvaluations(const RunData& r) { return !r.evaluations.empty(); }
bool HasSelectivity(const RunData& r) { return !r.selectivity.empty(); }

// undone / solved; none when no attempt began with a solved non-ancestor object.
std::optional<double> UndoneShare(double solved, double undone) {
  if (solved <= 0) return std::nullopt;
  return undone / solved;
}
std::optional<double> UndoneShare(const EvalPoint& p) {
  if (!p.has_compatibility) return std::nullopt;
  return UndoneShare(p.independent_solved, p.independent_undone);
}

// A run's undone share per evaluation, where it has one.
std::vector<std::pair<double, double>> UndoneCurve(const RunData& r) {
  std::vector<std::pair<double, double>> curve;
  for (const EvalPoint& p : r.evaluations)
    if (const auto share = UndoneShare(p)) curve.emplace_back(p.env_steps, *share);
  return curve;
}
bool HasUndone(const RunData& r) { return !UndoneCurve(r).empty(); }

// A legend's "method (N seeds)": N counts the runs that draw in the figure (by default those
// with at least one evaluation of a trained policy; a run just started has none).
std::string LegendTitle(const std::string& method, const Group& group, HasData has_data = HasEvaluations) {
  const auto seeds = std::count_if(group.begin(), group.end(), [&](const RunData* r) { return has_data(*r); });
  return method + " (" + std::to_string(seeds) + (seeds == 1 ? " seed" : " seeds") + ")";
}

int FinishedRuns(const Group& group) {
  return static_cast<int>(std::count_if(group.begin(), group.end(), [](const RunData* r) { return r->finished; }));
}

// The runs a table row summarizes: the finished ones where a method has any (an unfinished
// run's last evaluation comes from a smaller budget), else all of them.
Group CountedRuns(const Group& group) {
  if (FinishedRuns(group) == 0) return group;
  Group counted;
  for (const RunData* r : group)
    if (r->finished) counted.push_back(r);
  return counted;
}

Groups GroupRuns(const std::vector<RunData>& runs) {
  Groups groups;
  for (const RunData& r : runs) groups[r.environment][r.method].push_back(&r);
  for (auto& [env, methods] : groups)
    for (auto& [method, group] : methods)
      std::sort(group.begin(), group.end(), [](const RunData* a, const RunData* b) { return a->seed < b->seed; });
  return groups;
}

// The names of a group's subgoal entities, as many as its final evaluations report: "arm",
// then "object N", N the catalogue number when every run of the group plays the same single
// object set (a held-out combination), else the place in the episode.
std::vector<std::string> EntityNames(const std::map<std::string, Group>& methods) {
  size_t entities = 0;
  std::optional<std::vector<int>> objects;
  bool same_objects = true;
  for (const auto& [method, group] : methods)
    for (const RunData* r : group) {
      if (!r->evaluations.empty()) entities = std::max(entities, r->evaluations.back().subgoal_success.size());
      same_objects = same_objects && (!objects || *objects == r->eval_objects);
      objects = r->eval_objects;
    }
  std::vector<std::string> names;
  for (size_t i = 0; i < entities; ++i)
    names.push_back(i == 0 ? "arm"
                           : "object " + std::to_string(same_objects && objects && i <= objects->size()
                                                            ? static_cast<size_t>((*objects)[i - 1])
                                                            : i));
  return names;
}

// The x values where a group's curves are drawn: every run's points, those closer than half
// the typical spacing merged (runs evaluate at slightly different step counts).
std::vector<double> CurveGrid(const std::vector<std::vector<std::pair<double, double>>>& curves, double* tolerance) {
  std::vector<double> xs, gaps;
  for (const auto& c : curves) {
    for (size_t i = 0; i < c.size(); ++i) {
      xs.push_back(c[i].first);
      if (i) gaps.push_back(c[i].first - c[i - 1].first);
    }
  }
  std::sort(xs.begin(), xs.end());
  std::sort(gaps.begin(), gaps.end());
  *tolerance = gaps.empty() ? 0 : 0.5 * gaps[gaps.size() / 2];
  std::vector<double> grid;
  for (size_t i = 0; i < xs.size();) {
    size_t j = i;
    double sum = 0;
    while (j < xs.size() && xs[j] - xs[i] <= *tolerance) sum += xs[j++];
    grid.push_back(sum / static_cast<double>(j - i));
    i = j;
  }
  return grid;
}

// A run's value at x: interpolated, or its end value within `tolerance` of its ends.
std::optional<double> ValueAt(const std::vector<std::pair<double, double>>& c, double x, double tolerance) {
  if (c.empty()) return std::nullopt;
  if (x < c.front().first && c.front().first - x <= tolerance) return c.front().second;
  if (x > c.back().first && x - c.back().first <= tolerance) return c.back().second;
  return Interpolate(c, x);
}

// Writes one figure's data: per method a block "x mean min max n sd" (blocks separated by two
// blank lines, gnuplot's `index`). Returns the methods with data, in block order.
std::vector<std::string> WriteCurveBlocks(
    const std::string& path, const std::map<std::string, Group>& methods,
    const std::function<std::vector<std::pair<double, double>>(const RunData&)>& curve_of) {
  std::ofstream out(path);
  out << "# per method (blocks in the order of the plot): env_steps mean min max seeds sample_sd\n";
  std::vector<std::string> written;
  for (const auto& [method, group] : methods) {
    std::vector<std::vector<std::pair<double, double>>> curves;
    for (const RunData* r : group) curves.push_back(curve_of(*r));
    double tolerance = 0;
    const std::vector<double> grid = CurveGrid(curves, &tolerance);
    if (grid.empty()) continue;
    out << "# " << method << "\n";
    for (double x : grid) {
      std::vector<double> values;
      for (const auto& c : curves)
        if (auto v = ValueAt(c, x, tolerance)) values.push_back(*v);
      if (values.empty()) continue;
      const Spread s = SpreadOf(values);
      out << x << ' ' << s.mean << ' ' << s.min << ' ' << s.max << ' ' << s.n << ' ' << s.std << '\n';
    }
    out << "\n\n";
    written.push_back(method);
  }
  return written;
}

const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

// The band's words for titles, and its bounds as gnuplot columns of a curve block.
std::string BandWords(CompareOptions::Band band) {
  return band == CompareOptions::Band::kStd ? "band ±1 sd over seeds" : "band min-max over seeds";
}
std::string BandColumns(CompareOptions::Band band) {
  return band == CompareOptions::Band::kStd ? "1:($2-$6):($2+$6)" : "1:3:4";
}

// The legend in two columns below the plot (the plot keeps the width, long names stay whole),
// at the bottom of the picture with a margin that holds its rows: gnuplot's own `key below`
// overlaps the x label.
std::string KeyBelow(size_t entries) {
  const size_t rows = (entries + 1) / 2;
  return "set key at screen 0.5, screen 0.01 center bottom horizontal maxcols 2 samplen 2 noenhanced\nset bmargin " +
         std::to_string(4 + rows) + "\n";
}

void PlotCurves(std::ostream& script, const std::string& png, const std::string& dat, const std::string& title,
                const std::string& ylabel, const std::vector<std::string>& methods,
                const std::map<std::string, Group>& groups, const std::map<std::string, double>& passive,
                CompareOptions::Band band, HasData has_data = HasEvaluations) {
  // file names relative to the script's folder (RunGnuplot runs there)
  const std::string png_name = fs::path(png).filename().string(), dat_name = fs::path(dat).filename().string();
  script << "set output '" << GnuplotQuote(png_name) << "'\n"
         << "set title '" << GnuplotQuote(title) << "' noenhanced\n"
         << "set xlabel 'environment steps'\nset ylabel '" << GnuplotQuote(ylabel) << "' noenhanced\n"
         << "set format x '%.0s%c'\n"
         << KeyBelow(methods.size() + passive.size()) << "set grid\nset yrange [0:*]\n"
         << "set style fill transparent solid 0.2 noborder\n"
         << "plot ";
  for (size_t i = 0; i < methods.size(); ++i) {
    const char* color = kColors[i % (sizeof kColors / sizeof *kColors)];
    script << (i ? ", " : "") << "'" << GnuplotQuote(dat_name) << "' index " << i << " using " << BandColumns(band)
           << " with filledcurves lc rgb '" << color << "' notitle, '' index " << i
           << " using 1:2 with linespoints lw 2 pt 7 ps 0.6 lc rgb '" << color << "' title '"
           << GnuplotQuote(LegendTitle(methods[i], groups.at(methods[i]), has_data)) << "'";
  }
  int k = 0;
  for (const auto& [label, value] : passive)
    script << ", " << value << " with lines dt 2 lw 2 lc rgb 'gray" << (k++ ? "40" : "") << "' title 'passive policy"
           << (passive.size() > 1 ? " (" + GnuplotQuote(label) + ")" : std::string()) << "'";
  script << "\n";
}

}  // namespace

std::string FinalTable(const std::vector<RunData>& runs) {
  std::ostringstream out;
  out << "# Final figures (srics compare)\n\n"
      << "Each run's final evaluation (its last one, never its best), as mean ± sample standard deviation over "
         "seeds; n = seeds. Where a method has finished runs, only those count (an unfinished run's last evaluation "
         "comes from a smaller budget); a method without any shows its unfinished runs' last evaluations. "
         "Distances in metres at the final step of evaluation episodes; success per subgoal as "
         "a fraction of evaluation episodes. Training selectivity: the last train.csv window, measured with the "
         "ancestor sets of the table's graph by construction (the same for every method); marked * where a run "
         "logged only its episodes' own ancestor sets (written before that column existed; SMORL has none, so the "
         "arm that pushes counts against it). Avg object distance / passive's: each run's final object distance over "
         "its own passive policy's (each seed draws its own evaluation goals). The figures' bands: mean ± 1 sample "
         "standard deviation over seeds (srics compare --band minmax: minimum to maximum).\n";
  for (const auto& [env, methods] : GroupRuns(runs)) {
    const std::vector<std::string> names = EntityNames(methods);
    const size_t entities = names.size();
    out << "\n## " << env
        << "\n\n| method | n | finished | env steps | avg distance (arm incl.) | avg object distance | "
           "success rate |";
    for (size_t i = 0; i < entities; ++i) out << " success " << names[i] << " |";
    out << " training selectivity | passive avg distance | avg object distance / passive's "
           "|\n|---|---|---|---|---|---|---|";
    for (size_t i = 0; i < entities; ++i) out << "---|";
    out << "---|---|---|\n";
    for (const auto& [method, group] : methods) {
      std::vector<double> steps, distance, object, success, selectivity, passive, object_ratio;
      bool own_ancestor_selectivity = false;
      std::vector<std::vector<double>> subgoal(entities);
      const int finished = FinishedRuns(group);
      for (const RunData* r : CountedRuns(group)) {
        if (r->passive) passive.push_back(r->passive->avg_distance);
        if (!r->selectivity.empty()) {
          selectivity.push_back(r->selectivity.back().second);
          own_ancestor_selectivity |= !r->selectivity_with_table_graph;
        }
        if (r->evaluations.empty()) continue;
        const EvalPoint& last = r->evaluations.back();
        // each seed draws its own evaluation goals: its passive policy is its yardstick
        if (r->passive && r->passive->avg_object_distance > 0)
          object_ratio.push_back(last.avg_object_distance / r->passive->avg_object_distance);
        steps.push_back(last.env_steps);
        distance.push_back(last.avg_distance);
        object.push_back(last.avg_object_distance);
        success.push_back(last.success_rate);
        for (size_t i = 0; i < entities; ++i)
          if (i < last.subgoal_success.size()) subgoal[i].push_back(last.subgoal_success[i]);
      }
      const Spread d = SpreadOf(distance);
      out << "| " << method << " | " << d.n << " | " << finished << "/" << group.size() << " | "
          << (steps.empty() ? "-" : Format(SpreadOf(steps).mean, 0)) << " | " << MeanStd(d) << " | "
          << MeanStd(SpreadOf(object)) << " | " << MeanStd(SpreadOf(success), 2) << " |";
      for (size_t i = 0; i < entities; ++i) out << " " << MeanStd(SpreadOf(subgoal[i]), 2) << " |";
      out << " " << MeanStd(SpreadOf(selectivity)) << (own_ancestor_selectivity ? " *" : "") << " | "
          << MeanStd(SpreadOf(passive)) << " | " << MeanStd(SpreadOf(object_ratio), 2) << " |\n";
    }
    out << "\nLate and compatibility: each run's mean over its last five evaluations (the curve's end, not "
           "one evaluation of few episodes); the undone share of its final evaluation (of the solved objects "
           "that were not the attempted entity's ancestors, the share an attempt undid; eval.csv since "
           "2026-12-04); and the final evaluation of its last checkpoint by `srics eval` where the run "
           "folder has one (final-eval/ or the folder `--final-eval` names, its passive policy on the same goals "
           "beside it in NAME-passive/); of its attempts on movable objects (not the arm, not a static object) the "
           "share of the solved subgoal entities they undid, ancestors too (attempts.csv others_solved and "
           "others_undone: every other subgoal entity of the protocol the evaluation played counts).\n\n"
           "| method | n | avg distance, last 5 | avg object distance, last 5 | undone share, last eval | final eval: "
           "episodes "
           "| avg distance | avg object distance | object / passive's | undone share | undone share, object attempts "
           "(ancestors too) |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& [method, group] : methods) {
      std::vector<double> late_distance, late_object, undone, episodes, final_distance, final_object, final_ratio,
          final_undone, object_undone;
      for (const RunData* r : CountedRuns(group)) {
        if (!r->evaluations.empty()) {
          const size_t from = r->evaluations.size() > 5 ? r->evaluations.size() - 5 : 0;
          double d = 0, o = 0;
          for (size_t i = from; i < r->evaluations.size(); ++i)
            d += r->evaluations[i].avg_distance, o += r->evaluations[i].avg_object_distance;
          late_distance.push_back(d / (r->evaluations.size() - from));
          late_object.push_back(o / (r->evaluations.size() - from));
          if (const auto share = UndoneShare(r->evaluations.back())) undone.push_back(*share);
        }
        if (const auto& f = r->final_evaluation) {
          episodes.push_back(f->episodes);
          final_distance.push_back(f->avg_distance);
          final_object.push_back(f->avg_object_distance);
          if (f->passive_object_distance > 0)
            final_ratio.push_back(f->avg_object_distance / f->passive_object_distance);
          if (const auto share = UndoneShare(f->independent_solved, f->independent_undone))
            final_undone.push_back(*share);
          if (f->object_attempt_solved && f->object_attempt_undone)
            if (const auto share = UndoneShare(*f->object_attempt_solved, *f->object_attempt_undone))
              object_undone.push_back(*share);
        }
      }
      out << "| " << method << " | " << late_distance.size() << " | " << MeanStd(SpreadOf(late_distance)) << " | "
          << MeanStd(SpreadOf(late_object)) << " | " << MeanStd(SpreadOf(undone), 2) << " | "
          << (episodes.empty() ? "-" : Format(SpreadOf(episodes).mean, 0) + " x " + std::to_string(episodes.size()))
          << " | " << MeanStd(SpreadOf(final_distance)) << " | " << MeanStd(SpreadOf(final_object)) << " | "
          << MeanStd(SpreadOf(final_ratio), 2) << " | " << MeanStd(SpreadOf(final_undone), 2) << " | "
          << MeanStd(SpreadOf(object_undone), 2) << " |\n";
    }
    bool any_graph = false;
    for (const auto& [method, group] : methods)
      for (const RunData* r : group) any_graph |= !r->graph.empty();
    if (any_graph) {
      out << "\nLearned graphs (graph.json of each run; pictures " << env << "-<run>-graph.png):\n\n"
          << "| run | learned graph | by construction | same |\n|---|---|---|---|\n";
      for (const auto& [method, group] : methods)
        for (const RunData* r : group) {
          if (r->graph.empty()) continue;
          const std::string& truth = r->graph_by_construction;
          out << "| " << fs::path(r->dir).filename().string() << " | " << r->graph << " | "
              << (truth.empty() ? "-" : truth) << " | "
              << (truth.empty()       ? "-"
                  : truth == r->graph ? "yes"
                                      : "no")
              << " |\n";
        }
    }
    out << "\nRuns:";
    for (const auto& [method, group] : methods)
      for (const RunData* r : group)
        out << " " << fs::path(r->dir).filename().string() << (r->finished ? "" : " (not finished)") << ";";
    out << "\n";
  }
  return out.str();
}

int Compare(const CompareOptions& options) {
  std::vector<std::string> warnings;
  std::vector<RunData> runs = ReadRuns(options.dirs, &warnings, options.final_eval);
  if (!options.methods.empty()) {
    const std::set<std::string> wanted(options.methods.begin(), options.methods.end());
    std::set<std::string> found;
    std::vector<RunData> picked;
    for (RunData& r : runs) {
      if (!wanted.count(r.method)) continue;
      found.insert(r.method);
      picked.push_back(std::move(r));
    }
    for (const std::string& m : wanted)
      if (!found.count(m)) warnings.push_back("--methods: no run of method '" + m + "'");
    runs = std::move(picked);
  }
  for (const std::string& w : warnings) std::cerr << "srics compare: " << w << "\n";
  if (runs.empty()) {
    std::cerr << "srics compare: no runs found\n";
    return 1;
  }
  const std::string out_dir = !options.out_dir.empty()   ? options.out_dir
                              : options.dirs.size() == 1 ? options.dirs[0] + "/compare"
                                                         : std::string("compare");
  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error) throw std::runtime_error("cannot create " + out_dir + ": " + error.message());
  const std::string out = fs::absolute(out_dir).lexically_normal().string();
  const std::string table_name = options.panel.empty() ? "results.md" : "results-" + options.panel + ".md";
  {
    std::ofstream table(out + "/" + table_name);
    table << FinalTable(runs);
    if (!table) throw std::runtime_error("cannot write " + out + "/" + table_name);
  }
  int code = 0;
  std::vector<std::string> pictures;
  for (const auto& [env, methods] : GroupRuns(runs)) {
    const std::string base = out + "/" + env + (options.panel.empty() ? "" : "-" + options.panel);
    const std::string figure = env + (options.panel.empty() ? "" : " (" + options.panel + ")");
    const std::string band = BandWords(options.band);
    std::map<std::string, double> passive_distance, passive_object;
    {
      std::vector<double> d, o;
      for (const auto& [method, group] : methods)
        for (const RunData* r : group)
          if (r->passive) d.push_back(r->passive->avg_distance), o.push_back(r->passive->avg_object_distance);
      if (!d.empty()) passive_distance[env] = SpreadOf(d).mean, passive_object[env] = SpreadOf(o).mean;
    }
    std::ofstream script(base + ".gnuplot");
    script << "set terminal pngcairo size 1000,650 font 'sans,11'\n";
    const auto distance = WriteCurveBlocks(base + "-distance.dat", methods, [](const RunData& r) {
      std::vector<std::pair<double, double>> c;
      for (const EvalPoint& p : r.evaluations) c.emplace_back(p.env_steps, p.avg_distance);
      return c;
    });
    PlotCurves(script, base + "-distance.png", base + "-distance.dat",
               figure + ": average distance of all entities, arm included (mean, " + band + ")",
               "final distance to goal (m)", distance, methods, passive_distance, options.band);
    pictures.push_back(base + "-distance.png");
    const auto object = WriteCurveBlocks(base + "-object_distance.dat", methods, [](const RunData& r) {
      std::vector<std::pair<double, double>> c;
      for (const EvalPoint& p : r.evaluations) c.emplace_back(p.env_steps, p.avg_object_distance);
      return c;
    });
    PlotCurves(script, base + "-object_distance.png", base + "-object_distance.dat",
               figure + ": average object distance (mean, " + band + ")", "final distance to goal (m)", object, methods,
               passive_object, options.band);
    pictures.push_back(base + "-object_distance.png");
    bool any_selectivity = false;
    for (const auto& [method, group] : methods)
      for (const RunData* r : group) any_selectivity |= !r->selectivity.empty();
    if (any_selectivity) {
      const auto selectivity =
          WriteCurveBlocks(base + "-selectivity.dat", methods, [](const RunData& r) { return r.selectivity; });
      PlotCurves(script, base + "-selectivity.png", base + "-selectivity.dat",
                 figure + ": selectivity of training episodes, the table's ancestor sets (mean, " + band + ")",
                 "selectivity", selectivity, methods, {}, options.band, HasSelectivity);
      pictures.push_back(base + "-selectivity.png");
    }
    bool any_undone = false;
    for (const auto& [method, group] : methods)
      for (const RunData* r : group) any_undone |= HasUndone(*r);
    if (any_undone) {
      const auto undone = WriteCurveBlocks(base + "-undone.dat", methods, UndoneCurve);
      PlotCurves(script, base + "-undone.png", base + "-undone.dat",
                 figure + ": solved non-ancestor objects an attempt undid (mean, " + band + ")", "share undone", undone,
                 methods, {}, options.band, HasUndone);
      pictures.push_back(base + "-undone.png");
    }
    // per-subgoal success at the final evaluation: one bar per method and entity
    const std::vector<std::string> names = EntityNames(methods);
    const size_t entities = names.size();
    if (entities > 0) {
      std::ofstream bars(base + "-subgoal_success.dat");
      const bool std_bars = options.band == CompareOptions::Band::kStd;
      bars << "# entity, then per method: mean and the error bar's ends ("
           << (std_bars ? "mean ± 1 sample sd" : "min, max")
           << ") over seeds of the final evaluation's success\n# entity";
      for (const auto& [method, group] : methods) bars << ' ' << method << (std_bars ? " low high" : " min max");
      bars << '\n';
      for (size_t i = 0; i < entities; ++i) {
        bars << '"' << names[i] << '"';
        for (const auto& [method, group] : methods) {
          std::vector<double> values;
          for (const RunData* r : group)
            if (!r->evaluations.empty() && i < r->evaluations.back().subgoal_success.size())
              values.push_back(r->evaluations.back().subgoal_success[i]);
          const Spread s = SpreadOf(values);
          if (std_bars)
            bars << ' ' << s.mean << ' ' << s.mean - s.std << ' ' << s.mean + s.std;
          else
            bars << ' ' << s.mean << ' ' << s.min << ' ' << s.max;
        }
        bars << '\n';
      }
      script
          << "set output '" << GnuplotQuote(fs::path(base).filename().string() + "-subgoal_success.png") << "'\n"
          << "set title '" << GnuplotQuote(figure) << ": success per subgoal at the final evaluation (mean, "
          << (std_bars ? "bars ±1 sd" : "bars min-max") << " over seeds)' noenhanced\n"
          << "set xlabel ''\nset ylabel 'success rate'\nset yrange [0:1.05]\nset grid ytics\n"
          << "set format x '% h'\n"
          << KeyBelow(methods.size())
          << "set style data histograms\nset style histogram errorbars gap 2 lw 1\nset style fill solid 0.8 border -1\n"
          << "set bars 2\nplot ";
      size_t k = 0;
      for (const auto& [method, group] : methods) {
        const size_t column = 2 + 3 * k;
        script << (k ? ", " : "") << "'" << GnuplotQuote(fs::path(base).filename().string() + "-subgoal_success.dat")
               << "' using " << column << ":" << column + 1 << ":" << column + 2 << (k ? "" : ":xtic(1)") << " lc rgb '"
               << kColors[k % (sizeof kColors / sizeof *kColors)] << "' title '"
               << GnuplotQuote(LegendTitle(method, group)) << "'";
        ++k;
      }
      script << "\n";
      pictures.push_back(base + "-subgoal_success.png");
    }
    for (const auto& [method, group] : methods)
      for (const RunData* r : group) {
        const std::string copy = out + "/" + env + "-" + fs::path(r->dir).filename().string() + "-graph.png";
        if (!r->graph_picture.empty()) {
          std::error_code copy_error;
          fs::copy_file(r->graph_picture, copy, fs::copy_options::overwrite_existing, copy_error);
          if (copy_error)
            std::cerr << "srics compare: cannot copy " << r->graph_picture << ": " << copy_error.message() << "\n";
          else
            pictures.push_back(copy);
        } else if (!r->graph_dot.empty()) {
          std::string draw_error;
          if (graph_file::RenderDotToPng(r->graph_dot, copy, &draw_error))
            pictures.push_back(copy);
          else
            std::cerr << "srics compare: " << r->dir << "/graph.json: " << draw_error << "\n";
        }
      }
    script.close();
    std::string plot_error;
    if (!RunGnuplot(base + ".gnuplot", &plot_error)) {
      std::cerr << "srics compare: " << env << ": " << plot_error << "\n";
      code = 1;
    }
  }
  std::cout << "srics compare: " << runs.size() << " runs; " << out << "/" << table_name;
  for (const std::string& p : pictures) std::cout << ", " << fs::path(p).filename().string();
  std::cout << "\n";
  return code;
}

}  // namespace srics::analysis
