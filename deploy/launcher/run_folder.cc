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

namespace {

std::string FormatTime(const char* format, const std::tm& time) {
  char buffer[64];
  return std::string(buffer, std::strftime(buffer, sizeof buffer, format, &time));
}

}  // namespace

std::string LocalTime(const char* format, std::time_t t) {
  std::tm local{};
  localtime_r(&t, &local);
  return FormatTime(format, local);
}

std::string UtcTime(const char* format, std::time_t t) {
  std::tm utc{};
  gmtime_r(&t, &utc);
  return FormatTime(format, utc);
}

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
  const std::string stamp = UtcTime("%Y%m%dT%H%M%S", static_cast<std::time_t>(ms / 1000));
  char id[96];
  std::snprintf(id, sizeof id, "%s-%d-%s.%03d", name.c_str(), static_cast<int>(getpid()), stamp.c_str(),
                static_cast<int>(ms % 1000));
  return id;
}

std::string ChooseRunId(const std::string& run_dir) {
  const std::string recorded = run_dir.empty() ? "" : config::RecordedRunId(run_dir + "/config.yaml");
  return recorded.empty() ? NewRunId() : recorded;
}

namespace {

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
  if (fs::exists(resolved)) {
    // the recorded settings as this binary resolves them: a setting added after the run
    // started is absent there and takes its default, which is what the run had
    std::string recorded;
    try {
      recorded = config::ParseRecordedConfig(WithoutComments(resolved.string()), resolved.string()).resolved_yaml;
    } catch (const config::ConfigError& e) {
      return std::string("its recorded settings no longer load: ") + e.what();
    }
    return FirstDifference(recorded + "\n", resolved_yaml + "\n");
  }
  const fs::path merged = fs::path(dir) / "config.yaml";
  if (!fs::exists(merged)) return "";
  return FirstDifference(WithoutComments(merged.string()), effective_yaml + "\n");
}

std::vector<std::string> WithEarlierDefaults(const std::string& dir, const std::vector<std::string>& overrides) {
  const fs::path resolved = fs::path(dir) / "resolved-config.yaml";
  if (dir.empty() || !fs::exists(resolved)) return overrides;
  std::vector<std::string> all;
  try {
    all = config::EarlierDefaultsOf(WithoutComments(resolved.string()), resolved.string());
  } catch (const config::ConfigError&) {
    return overrides;  // an unreadable record: CheckResumedConfig names it
  }
  all.insert(all.end(), overrides.begin(), overrides.end());
  return all;
}

void CheckResumedConfig(const config::Config& config, const std::string& dir, bool allow_change) {
  const fs::path path = fs::path(dir) / "config.yaml";
  const std::string difference = ConfigChangeSince(dir, config.effective_yaml, config.resolved_yaml);
  if (difference.empty()) return;
  if (!allow_change)
    throw std::invalid_argument("the configuration of " + dir + " changed since the run started (" + difference +
                                "): a continued run goes on with the configuration it started with; restore it, "
                                "or pass --allow-config-change (the change is then recorded in the folder)");
  const std::string stamp = UtcTime("%Y%m%dT%H%M%SZ");
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
    const fs::path base = fs::path(config.run.output_dir) / (config.run.name + "-" + LocalTime("%Y%m%d-%H%M%S"));
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

}  // namespace srics::launcher
