#include "deploy/dashboard/run_folder_source.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <variant>
#include <vector>

#include "common/config/config.h"
#include "common/files/small_file.h"
#include "common/graph_file/graph_file.h"
#include "common/transport/wire.h"
#include "deploy/monitor/csv_sink.h"
#include "deploy/run_folder/csv.h"

namespace srics::dashboard {
namespace {

namespace fs = std::filesystem;
namespace mon = srics::monitor;
namespace tr = srics::transport;

constexpr const char* kFiles[] = {"eval.csv", "learner.csv", "nodes.csv", "config.yaml", "graph.json", "outcome.yaml"};

std::optional<rl::NodePhase> ParseNodePhase(const std::string& name) {
  for (int s = 0; s <= static_cast<int>(rl::NodePhase::kFailed); ++s)
    if (name == rl::NodePhaseName(static_cast<rl::NodePhase>(s))) return static_cast<rl::NodePhase>(s);
  return std::nullopt;
}

// A row of any of the three files, for applying them in wall-time order.
struct NodeRow {
  std::string run_id;
  rl::NodeStatus status;
  std::string event;  // "lost" / "exited" rows: the monitor saw the node go (no new status)
};
struct EvalRow {
  std::string run_id;
  rl::EvalReport report;  // floats as the CSV holds them (the wire's precision)
};
struct LearnerRow {
  std::string run_id;
  rl::LearnerReport stats;  // floats as the CSV holds them (the wire's precision)
};
struct Timed {
  double wall = 0;
  std::variant<EvalRow, LearnerRow, NodeRow> sample;
};

// A row of eval.csv as the evaluation report it records.
EvalRow ParseEvalRow(const run_folder::CsvRow& r) {
  EvalRow row;
  row.run_id = r.TextOrThrow("run_id");
  rl::EvalReport& e = row.report;
  e.actor_id = static_cast<uint32_t>(r.Unsigned("actor_id"));
  e.policy_version = r.Unsigned("policy_version");
  e.graph_version = r.Unsigned("graph_version");
  e.env_steps = r.Unsigned("env_steps");
  rl::EvaluationSummary& s = e.summary;
  s.episodes = static_cast<int>(static_cast<uint32_t>(r.Unsigned("episodes")));
  s.avg_distance = r.Float("avg_distance");
  s.avg_object_distance = r.Float("avg_object_distance");
  s.success_rate = r.Float("success_rate");
  s.selectivity = r.Float("selectivity");
  s.selectivity_episodes = s.episodes;  // as received
  const std::vector<float> entity_distance = r.Floats("entity_distance");
  const std::vector<float> subgoal_success = r.Floats("subgoal_success");
  s.entity_distance.assign(entity_distance.begin(), entity_distance.end());
  s.subgoal_success.assign(subgoal_success.begin(), subgoal_success.end());
  return row;
}

// A row of learner.csv as the learner's stats; the budget is the run's config's (0: unknown).
LearnerRow ParseLearnerRow(const run_folder::CsvRow& r, uint64_t budget) {
  LearnerRow row;
  row.run_id = r.TextOrThrow("run_id");
  rl::LearnerReport& s = row.stats;
  s.updates = r.Unsigned("updates");
  s.transitions_inserted = r.Unsigned("transitions_inserted");
  s.replay_size = r.Unsigned("replay_size");
  s.episodes_accepted = r.Unsigned("episodes_accepted");
  s.episodes_rejected = r.Unsigned("episodes_rejected");
  s.policy_version = r.Unsigned("policy_version");
  s.q_loss = r.Float("q_loss");
  s.policy_loss = r.Float("policy_loss");
  s.alpha = r.Float("alpha");
  s.entropy = r.Float("entropy");
  s.updates_per_second = r.Float("updates_per_second");
  s.inserts_per_second = r.Float("inserts_per_second");
  s.mean_reward = r.Float("mean_reward");
  s.budget_env_steps = budget;
  return row;
}

// A row of nodes.csv as the node's status, or as the monitor seeing it go.
NodeRow ParseNodeRow(const run_folder::CsvRow& r) {
  NodeRow n;
  n.run_id = r.TextOrThrow("run_id");
  n.status.role = r.TextOrThrow("role");
  n.status.node_id = static_cast<uint32_t>(r.Unsigned("node_id"));
  n.status.host = r.TextOrThrow("host");
  n.status.pid = static_cast<int32_t>(r.Double("pid"));
  const std::string& state_name = r.TextOrThrow("state");
  if (state_name == "lost" || state_name == "exited") {
    n.event = state_name;
  } else {
    const std::optional<rl::NodePhase> parsed = ParseNodePhase(state_name);
    if (!parsed) throw std::invalid_argument("state: unknown");
    n.status.report.phase = *parsed;
  }
  n.status.report.policy_version = r.Unsigned("policy_version");
  n.status.report.graph_version = r.Unsigned("graph_version");
  n.status.report.steps = r.Unsigned("env_steps");
  n.status.report.dropped = r.Unsigned("dropped_samples");
  n.status.uptime_ms = r.Unsigned("uptime_ms");
  n.status.report.detail = r.TextOrThrow("detail");
  return n;
}

}  // namespace

RunFolderSource::RunFolderSource(std::string dir) : dir_(std::move(dir)) {
  std::error_code error;
  if (!fs::is_directory(dir_, error)) throw std::invalid_argument("run folder " + dir_ + " is not a folder");
  bool any = false;
  for (const char* file : kFiles) any |= fs::exists(fs::path(dir_) / file, error);
  if (!any)
    throw std::invalid_argument("run folder " + dir_ + " holds none of eval.csv, learner.csv, nodes.csv, config.yaml");
  render_.title = "run folder " + dir_;
}

bool RunFolderSource::Refresh(mon::Clock::time_point now) {
  bool changed = false;
  for (const char* file : kFiles) {
    std::error_code error;
    const fs::path path = fs::path(dir_) / file;
    std::pair<uintmax_t, fs::file_time_type> stamp{0, {}};
    if (fs::exists(path, error)) stamp = {fs::file_size(path, error), fs::last_write_time(path, error)};
    auto it = seen_.find(file);
    if (it == seen_.end() || it->second != stamp) changed = true;
    seen_[file] = stamp;
  }
  episode_ = FindLatestEpisode(dir_);
  if (changed) Rebuild(now);
  return changed;
}

void RunFolderSource::Rebuild(mon::Clock::time_point now) {
  const fs::path dir(dir_);
  mon::MonitorState state;
  render_ = mon::RenderOptions{};
  render_.title = "run folder " + dir_;
  uint64_t budget = 0;
  std::error_code error;
  if (fs::exists(dir / "config.yaml", error)) {
    try {
      const config::Config config = config::LoadConfig((dir / "config.yaml").string());
      state.lost_after = mon::LostAfter(config.transport);
      budget = config.run.total_env_steps;
      render_.total_env_steps = budget;
      render_.max_wall_minutes = config.run.max_wall_minutes;
    } catch (const std::exception&) {
      // a folder from another version: the budget stays unknown
    }
  }

  // every row of the three files, then applied in wall-time order
  uint64_t skipped = 0;
  std::vector<Timed> rows;
  auto read = [&](const char* file, auto parse) {
    run_folder::ForEachRow(
        dir / file,
        [&](const run_folder::CsvRow& r) {
          rows.push_back({r.Double("wall_time"), parse(r)});
        },
        &skipped);
  };
  read("eval.csv", ParseEvalRow);
  read("learner.csv", [budget](const run_folder::CsvRow& r) { return ParseLearnerRow(r, budget); });
  read("nodes.csv", ParseNodeRow);
  std::stable_sort(rows.begin(), rows.end(), [](const Timed& a, const Timed& b) { return a.wall < b.wall; });

  const double wall_now = mon::WallTimeNow();
  auto steady = [&](double wall) {
    const double age = std::max(0.0, wall_now - wall);
    return now - std::chrono::duration_cast<mon::Clock::duration>(std::chrono::duration<double>(age));
  };
  std::map<std::string, uint64_t> learner_env_steps;  // run id -> the learner's latest count
  for (Timed& row : rows) {
    const mon::Clock::time_point at = steady(row.wall);
    if (auto* e = std::get_if<EvalRow>(&row.sample)) {
      mon::Apply(&state, e->run_id, e->report, at);
    } else if (auto* s = std::get_if<LearnerRow>(&row.sample)) {
      s->stats.training_env_steps = learner_env_steps[s->run_id];
      mon::Apply(&state, s->run_id, s->stats, at);
    } else if (auto* n = std::get_if<NodeRow>(&row.sample)) {
      if (n->event.empty()) {
        if (n->status.role == "learner") learner_env_steps[n->run_id] = n->status.report.steps;
        mon::Apply(&state, n->run_id, n->status, at);
        continue;
      }
      // the monitor saw the node go: its last status stands (and with it the health the display
      // computes: LOST after a quiet without goodbye); "exited" means it said goodbye
      auto it =
          state.nodes.find({mon::PrintableText(n->run_id), mon::PrintableText(n->status.role), n->status.node_id});
      if (it != state.nodes.end() && n->event == "exited") it->second.status.report.phase = rl::NodePhase::kStopping;
    }
  }

  // the graph the graph service saved (or the one the run was given)
  if (fs::exists(dir / "graph.json", error)) {
    try {
      const rl::GraphUpdate graph =
          tr::AsReceived(graph_file::ToGraphUpdate(graph_file::LoadGraph((dir / "graph.json").string())));
      // the run it belongs to: the folder's (the one with the most rows), else none
      std::string run_id = state.runs.empty() ? std::string() : state.runs.begin()->first;
      for (const auto& [id, run] : state.runs)
        if (run.evals.size() > state.runs[run_id].evals.size()) run_id = id;
      const fs::file_time_type time = fs::last_write_time(dir / "graph.json", error);
      const double wall =
          std::chrono::duration<double>(std::chrono::file_clock::to_sys(time).time_since_epoch()).count();
      mon::Apply(&state, run_id, graph, steady(wall));
    } catch (const std::exception&) {
      ++skipped;  // a graph that does not load is not shown
    }
  }
  // a learner that stopped reporting has no rate (the display would show its last minute's)
  for (auto& [id, run] : state.runs)
    if (now - run.learner_received > state.lost_after) run.step_history.clear();

  // how the run ended, when it did (outcome.yaml: state and reason lines)
  std::istringstream outcome;
  try {
    if (fs::exists(dir / "outcome.yaml")) outcome.str(files::ReadSmallFile((dir / "outcome.yaml").string()));
  } catch (const files::SmallFileError&) {
    ++skipped;  // not this run's: over the size limit
  }
  std::string ended, reason;
  for (std::string line; std::getline(outcome, line);) {
    if (line.rfind("state: ", 0) == 0) ended = line.substr(7);
    if (line.rfind("reason: ", 0) == 0) reason = line.substr(8);
  }
  if (reason.size() >= 2 && reason.front() == '"' && reason.back() == '"') reason = reason.substr(1, reason.size() - 2);
  if (!ended.empty()) render_.title += "  (" + ended + (reason.empty() ? "" : ": " + reason) + ")";
  state_ = std::move(state);
  skipped_rows_ = skipped;
}

}  // namespace srics::dashboard
