#include "deploy/launcher/run_folder.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/files/durable_file.h"
#include "common/files/shell_path.h"
#include "common/files/small_file.h"
#include "common/graph_file/graph_file.h"
#include "common/rl/ground_truth.h"
#include "deploy/run_folder/csv.h"

namespace srics::launcher {

void SeedGraphFile(const config::Config& config, const std::string& dir) {
  const config::GraphConfig& g = config.graph;
  if (!g.ground_truth && g.file.empty()) return;
  if (dir.empty()) throw std::runtime_error("a given graph (graph.ground_truth or graph.file) needs a run folder");
  const std::string path = dir + "/graph.json";
  if (std::filesystem::exists(path)) return;
  graph_file::LearnedGraph learned;
  if (!g.file.empty()) {
    learned = graph_file::LoadGraph(g.file);  // validated: the file is untrusted
  } else {
    const rl::InteractionGraph truth = rl::GroundTruthGraph(config.env);
    const int n = truth.num_entities;
    std::vector<double> weights(static_cast<size_t>(n) * n, 0.0);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) weights[i * n + j] = i != j && truth.edge(i, j) ? 1.0 : 0.0;
    learned = graph_file::AggregateGraph(n, weights, g.threshold, truth.action_entity);
    learned.version = 1;
    // entity i is catalogue kind i (every object present); only the action's own entity
    // follows the action (nothing was measured: the numbers say so)
    for (int i = 0; i < n; ++i) {
      learned.entity_kinds.push_back(i);
      learned.action_correlation.push_back(i == truth.action_entity ? 1.0 : 0.0);
    }
  }
  graph_file::SaveGraphWithPictures(learned, dir + "/graph");
}
namespace fs = std::filesystem;

std::string NewRunId() {
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "host");
  std::string name;
  for (const char* c = host; *c && name.size() < 16; ++c)
    name += std::isalnum(static_cast<unsigned char>(*c)) || *c == '-' || *c == '_' ? *c : '_';
  if (name.empty()) name = "host";
  // milliseconds since the epoch, strictly increasing within this process
  static std::atomic<int64_t> last{0};
  const int64_t now =
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count();
  int64_t previous = last.load(), ms = 0;
  do {
    ms = std::max(now, previous + 1);
  } while (!last.compare_exchange_weak(previous, ms));
  const std::time_t seconds = static_cast<std::time_t>(ms / 1000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%S", &utc);
  char id[96];
  std::snprintf(id, sizeof id, "%s-%d-%s.%03d", name.c_str(), static_cast<int>(getpid()), stamp,
                static_cast<int>(ms % 1000));
  return id;
}

std::string ChooseRunId(const std::string& run_dir) {
  const std::string recorded = run_dir.empty() ? "" : config::RecordedRunId(run_dir + "/config.yaml");
  return recorded.empty() ? NewRunId() : recorded;
}

namespace {

std::string Timestamp() {
  const std::time_t t = std::time(nullptr);
  std::tm local{};
  localtime_r(&t, &local);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y%m%d-%H%M%S", &local);
  return buffer;
}

bool IsExecutable(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(path, error) && access(path.c_str(), X_OK) == 0;
}

}  // namespace

// A file's lines that are not comments.
std::string WithoutComments(const std::string& path) {
  std::istringstream in(fs::exists(path) ? files::ReadSmallFile(path) : std::string());
  std::string out;
  for (std::string line; std::getline(in, line);)
    if (line.rfind('#', 0) != 0) out += line + "\n";
  return out;
}

// The first line where two texts differ, for messages.
std::string FirstDifference(const std::string& a, const std::string& b) {
  std::stringstream x(a), y(b);
  std::string la, lb;
  for (int line = 1;; ++line) {
    const bool ha = static_cast<bool>(std::getline(x, la)), hb = static_cast<bool>(std::getline(y, lb));
    if (!ha && !hb) return "";
    if (!ha) la = "<end>";
    if (!hb) lb = "<end>";
    if (la != lb) return "line " + std::to_string(line) + ": '" + la + "' now '" + lb + "'";
  }
}

std::string ConfigChangeSince(const std::string& dir, const std::string& effective_yaml,
                              const std::string& resolved_yaml) {
  if (dir.empty()) return "";
  const fs::path resolved = fs::path(dir) / "resolved-config.yaml";
  if (fs::exists(resolved)) return FirstDifference(WithoutComments(resolved.string()), resolved_yaml + "\n");
  const fs::path merged = fs::path(dir) / "config.yaml";
  if (!fs::exists(merged)) return "";
  return FirstDifference(WithoutComments(merged.string()), effective_yaml + "\n");
}

void CheckResumedConfig(const config::Config& config, const std::string& dir, bool allow_change) {
  const fs::path path = fs::path(dir) / "config.yaml";
  const std::string difference = ConfigChangeSince(dir, config.effective_yaml, config.resolved_yaml);
  if (difference.empty()) return;
  if (!allow_change)
    throw std::invalid_argument("the configuration of " + dir + " changed since the run started (" + difference +
                                "): a continued run goes on with the configuration it started with; restore it, "
                                "or pass --allow-config-change (the change is then recorded in the folder)");
  const std::time_t t = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &utc);
  std::error_code error;
  fs::copy_file(path, path.string() + "." + stamp, fs::copy_options::overwrite_existing, error);
  const fs::path resolved = fs::path(dir) / "resolved-config.yaml";
  if (!error && fs::exists(resolved))
    fs::copy_file(resolved, resolved.string() + "." + stamp, fs::copy_options::overwrite_existing, error);
  if (error) throw std::runtime_error("cannot keep the previous " + path.string() + ": " + error.message());
  std::ofstream log(fs::path(dir) / "config-changes.log", std::ios::app);
  log << stamp << " --allow-config-change: " << difference << " (previous file: config.yaml." << stamp << ")\n";
  if (!log) throw std::runtime_error("cannot write " + (fs::path(dir) / "config-changes.log").string());
}

std::string PrepareRunFolder(const config::Config& config, const std::string& requested) {
  fs::path dir;
  if (!requested.empty()) {
    dir = requested;
  } else {
    const fs::path base = fs::path(config.run.output_dir) / (config.run.name + "-" + Timestamp());
    dir = base;
    for (int k = 2; fs::exists(dir); ++k) dir = base.string() + "-" + std::to_string(k);
  }
  std::error_code error;
  fs::create_directories(dir / "logs", error);
  if (error) throw std::runtime_error("cannot create run folder " + (dir / "logs").string() + ": " + error.message());
  // durable: it records the run id a resumed run goes on with
  files::WriteFileDurably((dir / "config.yaml").string(),
                          "# effective configuration of this run (written by srics run from " + config.source_file +
                              ")\n" + config.effective_yaml + "\n");
  files::WriteFileDurably((dir / "resolved-config.yaml").string(),
                          "# every setting of this run, defaults filled in by the srics binary that wrote it (from " +
                              config.source_file + "); a continued run is compared with it\n" + config.resolved_yaml +
                              "\n");
  return fs::absolute(dir).lexically_normal().string();
}

std::string GnuplotQuote(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out;
}

std::string QuotedString(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\')
      out += '\\', out += c;
    else if (c == '\n')
      out += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20)
      out += ' ';
    else
      out += c;
  }
  return out + "\"";
}

namespace {

// The inverse of QuotedString (text that is not quoted is returned as it is).
std::string UnquotedString(const std::string& text) {
  if (text.size() < 2 || text.front() != '"' || text.back() != '"') return text;
  std::string out;
  for (size_t i = 1; i + 1 < text.size(); ++i) {
    if (text[i] == '\\' && i + 2 < text.size()) {
      ++i;
      out += text[i] == 'n' ? '\n' : text[i];
    } else {
      out += text[i];
    }
  }
  return out;
}

}  // namespace

void WriteRunOutcome(const std::string& dir, const RunOutcome& outcome) {
  std::ostringstream out;
  out << "# how this run ended (srics run): finished, interrupted or failed\n"
      << "state: " << outcome.state << "\nexit_code: " << outcome.exit_code
      << "\nreason: " << QuotedString(outcome.reason) << "\n";
  files::WriteFileDurably((fs::path(dir) / "outcome.yaml").string(), out.str());
}

std::optional<RunOutcome> ReadRunOutcome(const std::string& dir) {
  const fs::path path = fs::path(dir) / "outcome.yaml";
  if (!fs::exists(path)) return std::nullopt;
  std::istringstream in(files::ReadSmallFile(path.string()));  // throws over the size limit
  RunOutcome outcome;
  bool have_state = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("state: ", 0) == 0)
      outcome.state = line.substr(7), have_state = true;
    else if (line.rfind("exit_code: ", 0) == 0)
      outcome.exit_code = std::atoi(line.c_str() + 11);
    else if (line.rfind("reason: ", 0) == 0)
      outcome.reason = UnquotedString(line.substr(8));
  }
  if (!have_state) return std::nullopt;
  return outcome;
}

void RemoveRunOutcome(const std::string& dir) {
  std::error_code ignored;
  fs::remove(fs::path(dir) / "outcome.yaml", ignored);
}

std::string ExecutableDir() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (error) return ".";
  return exe.parent_path().string();
}

std::string FindProgram(const std::string& program, const std::string& build_subdir, const std::string& bin_dir) {
  std::vector<fs::path> candidates;
  if (!bin_dir.empty()) {
    candidates.push_back(fs::path(bin_dir) / program);
    candidates.push_back(fs::path(bin_dir) / build_subdir / program);
  } else {
    const fs::path here = ExecutableDir();
    candidates.push_back(here / program);
    // build/deploy/launcher/srics -> build/<subdir>/<program>
    candidates.push_back(here.parent_path().parent_path() / build_subdir / program);
  }
  std::string looked;
  for (const fs::path& candidate : candidates) {
    if (IsExecutable(candidate)) return fs::absolute(candidate).lexically_normal().string();
    looked += (looked.empty() ? "" : ", ") + candidate.lexically_normal().string();
  }
  throw std::runtime_error("cannot find the program " + program + " (looked at " + looked +
                           "); build it first (tests/build.sh) or pass --bin-dir");
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
         << "set output '" << GnuplotQuote(dir) << "/curve.png'\n"
         << "set title '" << GnuplotQuote(title) << "' noenhanced\n"
         << "set xlabel 'environment steps'\nset ylabel 'final distance to goal (m)'\n"
         << "set key outside right top\nset grid\nset yrange [0:*]\n";
  std::string plot = "plot '" + GnuplotQuote(dir) +
                     "/curve.dat' using 1:3 with linespoints lw 2 title 'avg object distance', "
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
    script << "set output '" << GnuplotQuote(dir) << "/subgoal_success.png'\n"
           << "set title 'per-subgoal success: " << GnuplotQuote(title) << "' noenhanced\n"
           << "set ylabel 'success rate'\nset yrange [0:1.05]\nplot ";
    for (size_t i = 0; i < curve.entities; ++i)
      script << (i ? ", " : "") << "'" << GnuplotQuote(dir) << "/curve.dat' using 1:" << 4 + i
             << " with linespoints lw 2 title 'entity " << i << "'";
    script << "\n";
  }
}

}  // namespace

bool RunGnuplot(const std::string& script_path, std::string* error) {
  const std::string command = "gnuplot " + files::ShellQuote(script_path) + " 2>&1";
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

}  // namespace srics::launcher
