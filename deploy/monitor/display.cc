#include "deploy/monitor/display.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>

namespace srics::monitor {
namespace {

std::string Format(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string Format(const char* format, ...) {
  char buffer[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buffer, sizeof buffer, format, args);
  va_end(args);
  return buffer;
}

// 1234567 -> "1,234,567"
std::string Thousands(uint64_t value) {
  std::string digits = std::to_string(value);
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string Seconds(Clock::duration d) { return Format("%.1fs", std::chrono::duration<double>(d).count()); }

std::string HoursMinutesSeconds(double seconds) {
  const auto s = static_cast<int64_t>(seconds);
  return Format("%02" PRId64 ":%02" PRId64 ":%02" PRId64, s / 3600, s / 60 % 60, s % 60);
}

// "  310/s  ETA 00:12:30" (the ETA only with a budget still ahead; "" without a rate)
std::string RateAndEta(const RunView& run, uint64_t steps, uint64_t budget, const char* unit) {
  const std::optional<double> rate = EnvStepRate(run);
  if (!rate) return "";
  std::string out = Format("  %.0f%s", *rate, unit);
  if (budget > steps && *rate > 0) out += "  ETA " + HoursMinutesSeconds(static_cast<double>(budget - steps) / *rate);
  return out;
}

std::string ProgressBar(uint64_t done, uint64_t total, int width) {
  const double fraction = total ? std::min(1.0, static_cast<double>(done) / static_cast<double>(total)) : 0.0;
  const int filled = static_cast<int>(fraction * width + 0.5);
  return "[" + std::string(filled, '#') + std::string(width - filled, '.') + "] " + Format("%.0f%%", 100.0 * fraction);
}

// "-46%" for how much `value` is below `baseline`
std::string Relative(double value, double baseline) {
  if (baseline <= 0) return "";
  return Format("%+.0f%%", 100.0 * (value - baseline) / baseline);
}

// "e0 1.00  e1 0.80" for a per-entity vector
std::string PerEntity(const std::vector<double>& values, const char* format) {
  std::string out;
  for (size_t i = 0; i < values.size(); ++i) {
    if (i) out += "  ";
    out += "e" + std::to_string(i) + " " + Format(format, values[i]);
  }
  return out.empty() ? "-" : out;
}

void RenderLearner(const RunView& run, Clock::time_point now, std::string* out) {
  if (!run.learner) {
    *out += "learner   no stats yet\n";
  } else {
    const rl::LearnerReport& s = *run.learner;
    *out += Format(
        "learner   updates %s (%.1f/s)  inserts %.1f/s  replay %s  episodes %s ok / %s bad  "
        "policy v%" PRIu64 "  (%s ago)\n",
        Thousands(s.updates).c_str(), s.updates_per_second, s.inserts_per_second, Thousands(s.replay_size).c_str(),
        Thousands(s.episodes_accepted).c_str(), Thousands(s.episodes_rejected).c_str(), s.policy_version,
        Seconds(now - run.learner_received).c_str());
    *out += Format("          q_loss %.4g  policy_loss %.4g  alpha %.4g  entropy %.3g  mean reward %.4g\n", s.q_loss,
                   s.policy_loss, s.alpha, s.entropy, s.mean_reward);
  }
  if (run.weights) {
    const WeightsInfo& w = *run.weights;
    *out += Format("weights   v%" PRIu64 " (%s updates, %s parameters = %.1f MB)  %s ago\n", w.version,
                   Thousands(w.update_count).c_str(), Thousands(w.num_parameters).c_str(),
                   static_cast<double>(w.num_parameters) * 4.0 / 1e6, Seconds(now - w.received).c_str());
  }
}

// What the run's graph service says it is doing (its status detail: "collecting: 120/1000
// episodes, 0 updates", "training: ..., held-out 0.0123"), "" when none has reported: before
// the first graph, the only sign of the graph phase.
std::string GraphServiceDetail(const MonitorState& state, const std::string& run_id) {
  const NodeEntry* newest = nullptr;
  for (const auto& [key, node] : state.nodes)
    if (key.run_id == run_id && key.role == "graph" && (!newest || node.last_seen > newest->last_seen)) newest = &node;
  return newest ? newest->status.report.detail : std::string();
}

void RenderGraph(const RunView& run, const std::string& service_detail, Clock::time_point now, std::string* out) {
  if (!run.graph) {
    *out += service_detail.empty() ? "graph     none yet\n"
                                   : "graph     none yet; the graph service: " + service_detail + "\n";
    return;
  }
  const rl::GraphUpdate& g = *run.graph;
  const size_t n = static_cast<size_t>(g.graph.num_entities);
  std::string edges;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) {
      const size_t k = i * n + j;
      if (i == j || k >= g.graph.adjacency.size() || !g.graph.adjacency[k]) continue;
      if (!edges.empty()) edges += ", ";
      edges += Format("%zu->%zu", i, j);
      if (k < g.mean_weights.size()) edges += Format(" %.2f", g.mean_weights[k]);
    }
  *out += Format("graph     v%" PRIu64
                 ": %zu entities, %zu edges (%s), action -> e%d, threshold %.2f, "
                 "held-out loss %.4g, %u episodes  (%s ago)\n",
                 g.version, n, EdgeCount(g), edges.empty() ? "none" : edges.c_str(), g.graph.action_entity, g.threshold,
                 g.held_out_loss, g.episodes_used, Seconds(now - run.graph_received).c_str());
  std::string depths;
  const std::vector<int>& depth = g.structure.depth;
  for (size_t i = 0; i < depth.size(); ++i) {
    if (i) depths += "  ";
    depths += "e" + std::to_string(i) + " " + (depth[i] < 0 ? std::string("-") : std::to_string(depth[i]));
  }
  *out += "          depth: " + (depths.empty() ? std::string("-") : depths) + "   (- = not controllable)\n";
}

void RenderEval(const RunView& run, size_t history_rows, std::string* out) {
  const rl::EvalReport* latest = LatestEval(run);
  if (!latest) {
    *out += "eval      no evaluation of a trained policy yet";
  } else {
    const rl::EvalReport& e = *latest;
    const rl::EvaluationSummary& s = e.summary;
    *out += Format("eval      policy v%" PRIu64
                   " at %s env steps (actor %u, %u episodes): object distance "
                   "%.4f  distance %.4f  success %.2f  selectivity %.3g\n",
                   e.policy_version, Thousands(e.env_steps).c_str(), e.actor_id, static_cast<uint32_t>(s.episodes),
                   s.avg_object_distance, s.avg_distance, s.success_rate, s.selectivity);
    *out += "          subgoal success: " + PerEntity(s.subgoal_success, "%.2f") + "\n";
    *out += "          entity distance: " + PerEntity(s.entity_distance, "%.3f") + "\n";
  }
  if (run.passive) {
    const rl::EvaluationSummary& p = run.passive->summary;
    std::string line = Format("%spassive   object distance %.4f  distance %.4f  success %.2f", latest ? "" : "\n",
                              p.avg_object_distance, p.avg_distance, p.success_rate);
    if (latest)
      line += "   -> trained: object distance " + Relative(latest->summary.avg_object_distance, p.avg_object_distance) +
              ", distance " + Relative(latest->summary.avg_distance, p.avg_distance);
    if (run.passive_refused) line += Format("   (%" PRIu64 " not this run's refused)", run.passive_refused);
    *out += line + "\n";
  } else {
    *out += latest ? "passive   no baseline yet" : "; no passive baseline yet";
    if (run.passive_refused) *out += Format(" (%" PRIu64 " not this run's refused)", run.passive_refused);
    *out += "\n";
  }
  if (run.evals.size() > 1 && history_rows > 0) {
    *out += "history   env steps    policy  obj.dist  distance  success\n";
    const size_t first = run.evals.size() > history_rows ? run.evals.size() - history_rows : 0;
    for (size_t i = first; i < run.evals.size(); ++i) {
      const rl::EvalReport& e = run.evals[i];
      *out += Format("          %11s  v%-5" PRIu64 " %8.4f  %8.4f  %7.2f\n", Thousands(e.env_steps).c_str(),
                     e.policy_version, e.summary.avg_object_distance, e.summary.avg_distance, e.summary.success_rate);
    }
  }
}

void RenderNodes(const MonitorState& state, Clock::time_point now, const RenderOptions& options, bool show_run,
                 std::string* out) {
  size_t alive = 0, quiet = 0, lost = 0, exited = 0, shown = 0;
  std::string rows;
  for (const auto& [key, node] : state.nodes) {
    if (!Shown(key.run_id, options)) continue;
    ++shown;
    const NodeHealth health = HealthOf(state, node, now);
    (health == NodeHealth::kAlive   ? alive
     : health == NodeHealth::kQuiet ? quiet
     : health == NodeHealth::kLost  ? lost
                                    : exited)++;
    const rl::NodeStatus& s = node.status;
    const rl::NodeReport& r = s.report;
    std::string row = show_run ? Format("  %-12.12s", key.run_id.c_str()) : std::string("  ");
    row += Format("%-8.8s %3u %-14.14s %7d %-10.10s %-6s %6" PRIu64 " %5" PRIu64 " %11s %7" PRIu64 " %9s %6s  %s\n",
                  s.role.c_str(), s.node_id, s.host.c_str(), s.pid, rl::NodePhaseName(r.phase), NodeHealthName(health),
                  r.policy_version, r.graph_version, Thousands(r.steps).c_str(), r.dropped,
                  HoursMinutesSeconds(static_cast<double>(s.uptime_ms) / 1000.0).c_str(),
                  Seconds(now - node.last_seen).c_str(), r.detail.c_str());
    rows += row;
  }
  *out += Format("nodes     %zu alive, %zu lost, %zu exited", alive, lost, exited);
  if (quiet) *out += Format(", %zu quiet (busy: no status lately, DDS liveliness fine)", quiet);
  if (state.evicted_nodes || state.evicted_runs)
    *out +=
        Format(", forgotten past the limits (transport.monitor_max_nodes / _runs): %" PRIu64 " nodes, %" PRIu64 " runs",
               state.evicted_nodes, state.evicted_runs);
  *out += Format("   (NodeStatus writers alive: %u, dropped malformed samples here: %" PRIu64 ")\n",
                 state.status_writers_alive, state.dropped_samples);
  if (shown == 0) {
    *out += "  none seen yet\n";
    return;
  }
  *out += (show_run ? Format("  %-12s", "RUN") : std::string("  ")) +
          Format("%-8s %3s %-14s %7s %-10s %-6s %6s %5s %11s %7s %9s %6s  %s\n", "ROLE", "ID", "HOST", "PID", "STATE",
                 "HEALTH", "POLICY", "GRAPH", "ENV STEPS", "DROPPED", "UPTIME", "LAST", "DETAIL");
  *out += rows;
}

void RenderProcesses(const RenderOptions& options, std::string* out) {
  if (options.processes.empty()) return;
  *out += "processes\n";
  *out += Format("  %-12s %7s %-24s %8s  %s\n", "NAME", "PID", "STATE", "RESTARTS", "LAST EXIT");
  for (const ProcessRow& p : options.processes)
    *out += Format("  %-12.12s %7s %-24.24s %8u  %s\n", p.name.c_str(), p.pid ? std::to_string(p.pid).c_str() : "-",
                   p.state.c_str(), p.restarts, p.last_exit.empty() ? "-" : p.last_exit.c_str());
}

}  // namespace

bool Shown(const std::string& run_id, const RenderOptions& options) {
  return options.run_id.empty() || options.run_id == run_id;
}

std::vector<std::string> ShownRunIds(const MonitorState& state, const RenderOptions& options) {
  std::vector<std::string> run_ids;
  for (const auto& [id, run] : state.runs)
    if (Shown(id, options)) run_ids.push_back(id);
  for (const auto& [key, node] : state.nodes)
    if (Shown(key.run_id, options) && std::find(run_ids.begin(), run_ids.end(), key.run_id) == run_ids.end())
      run_ids.push_back(key.run_id);
  std::sort(run_ids.begin(), run_ids.end());
  return run_ids;
}

std::string Render(const MonitorState& state, Clock::time_point now, const RenderOptions& options) {
  std::string out = options.title;
  if (options.elapsed_s >= 0) {
    out += "   elapsed " + HoursMinutesSeconds(options.elapsed_s);
    if (options.max_wall_minutes > 0) out += " / " + HoursMinutesSeconds(options.max_wall_minutes * 60.0);
  }
  out += "\n";
  const std::vector<std::string> run_ids = ShownRunIds(state, options);
  if (run_ids.empty()) out += "\nnothing received yet (same domain id, run id and Cyclone profile?)\n";
  static const RunView kEmpty;
  for (const std::string& id : run_ids) {
    auto it = state.runs.find(id);
    const RunView& run = it == state.runs.end() ? kEmpty : it->second;
    const uint64_t steps = EnvSteps(run);
    const uint64_t budget = BudgetEnvSteps(run) > 0 ? BudgetEnvSteps(run) : options.total_env_steps;
    out += "\nrun " + id + "   env steps " + Thousands(steps);
    if (budget > 0) out += " / " + Thousands(budget) + " " + ProgressBar(steps, budget, 30);
    out += RateAndEta(run, steps, budget, "/s") + "\n";
    RenderLearner(run, now, &out);
    RenderGraph(run, GraphServiceDetail(state, id), now, &out);
    RenderEval(run, options.history_rows, &out);
  }
  out += "\n";
  RenderNodes(state, now, options, run_ids.size() > 1, &out);
  if (!options.processes.empty()) {
    out += "\n";
    RenderProcesses(options, &out);
  }
  if (!options.events.empty()) {
    out += "\nevents\n";
    for (const std::string& event : options.events) out += "  " + event + "\n";
  }
  return out;
}

std::string RenderOneLine(const MonitorState& state, Clock::time_point now, const std::string& run_id,
                          uint64_t total_env_steps) {
  static const RunView kEmpty;
  auto it = state.runs.find(run_id);
  const RunView& run = it == state.runs.end() ? kEmpty : it->second;
  std::string out = "steps " + Thousands(EnvSteps(run));
  if (BudgetEnvSteps(run) > 0) total_env_steps = BudgetEnvSteps(run);
  if (total_env_steps) out += "/" + Thousands(total_env_steps);
  out += RateAndEta(run, EnvSteps(run), total_env_steps, " steps/s");
  out += "  updates " + Thousands(run.learner ? run.learner->updates : 0);
  if (const rl::EvalReport* e = LatestEval(run)) {
    out += Format("  eval v%" PRIu64 " obj.dist %.4f", e->policy_version, e->summary.avg_object_distance);
    if (run.passive) out += " (passive " + Format("%.4f", run.passive->summary.avg_object_distance) + ")";
  } else {
    out += "  eval -";
  }
  if (run.graph) {
    out += Format("  graph v%" PRIu64 " %zu edges", run.graph->version, EdgeCount(*run.graph));
  } else {
    const std::string detail = GraphServiceDetail(state, run_id);
    out += detail.empty() ? std::string("  graph -") : "  graph: " + detail;
  }
  size_t alive = 0, gone = 0;
  for (const auto& [key, node] : state.nodes) {
    if (key.run_id != run_id) continue;
    const NodeHealth health = HealthOf(state, node, now);
    (health == NodeHealth::kAlive || health == NodeHealth::kQuiet ? alive : gone)++;
  }
  out += Format("  nodes %zu alive", alive);
  if (gone) out += Format(", %zu gone", gone);
  return out;
}

size_t ChooseOutputWidth(bool is_terminal, int terminal_columns, const char* columns_env) {
  if (!is_terminal) return 0;
  if (terminal_columns > 0) return static_cast<size_t>(terminal_columns);
  if (columns_env != nullptr) {
    char* end = nullptr;
    const long columns = std::strtol(columns_env, &end, 10);
    if (end != columns_env && *end == '\0' && columns > 0 && columns < 100000) return static_cast<size_t>(columns);
  }
  return 0;
}

size_t OutputWidth(int fd) {
  const bool terminal = isatty(fd) == 1;
  winsize size{};
  const int columns = terminal && ioctl(fd, TIOCGWINSZ, &size) == 0 ? size.ws_col : 0;
  return ChooseOutputWidth(terminal, columns, std::getenv("COLUMNS"));
}

std::string ClipLines(const std::string& text, size_t width) {
  if (width == 0) return text;
  std::string out;
  out.reserve(text.size());
  size_t column = 0;     // characters of the current line so far
  bool cutting = false;  // the current line is past the width
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      out += c;
      column = 0;
      cutting = false;
      continue;
    }
    if (cutting) continue;
    const bool continuation = (static_cast<unsigned char>(c) & 0xC0) == 0x80;  // inside a UTF-8 character
    if (!continuation && column == width) {
      // the line is longer: its last column becomes the mark (a byte-wise cut of the last
      // character may leave its first byte only: drop the character)
      size_t back = out.size();
      while (back > 0 && (static_cast<unsigned char>(out[back - 1]) & 0xC0) == 0x80) --back;
      if (back > 0) out.resize(back - 1);
      out += '~';
      cutting = true;
      continue;
    }
    if (!continuation) ++column;
    out += c;
  }
  return out;
}

}  // namespace srics::monitor
