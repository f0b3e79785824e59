#include "deploy/monitor/csv_sink.h"

#include "deploy/monitor/monitor_state.h"
#include "deploy/run_folder/csv.h"
#include "deploy/run_folder/schema.h"

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace srics::monitor {
namespace {

void Open(const std::string& path, const std::string& header, std::ofstream* out) {
  std::error_code error;
  const bool empty = !std::filesystem::exists(path, error) || std::filesystem::file_size(path, error) == 0;
  out->open(path, std::ios::out | std::ios::app);
  if (!*out) throw std::runtime_error("cannot open " + path + " for appending");
  *out << std::setprecision(7);
  if (empty) *out << header << '\n' << std::flush;
}

std::string Time(double wall_time) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(3) << wall_time;
  return out.str();
}

}  // namespace

std::string CsvField(const std::string& raw) {
  return run_folder::QuoteCsvField(PrintableText(raw));  // a peer's string: no control characters
}

double WallTimeNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

CsvSink::CsvSink(const std::string& dir) : dir_(dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw std::runtime_error("cannot create " + dir + ": " + error.message());
  Open(dir + "/eval.csv", run_folder::HeaderLine(run_folder::kEvalColumns), &eval_);
  Open(dir + "/learner.csv", run_folder::HeaderLine(run_folder::kLearnerColumns), &learner_);
  Open(dir + "/nodes.csv", run_folder::HeaderLine(run_folder::kNodesColumns), &nodes_);
}

void CsvSink::Append(const std::string& run_id, const rl::EvalReport& e, double wall_time) {
  const rl::EvaluationSummary& r = e.summary;
  // episodes as the wire counts them (unsigned)
  eval_ << Time(wall_time) << ',' << CsvField(run_id) << ',' << e.actor_id << ',' << e.policy_version << ','
        << e.graph_version << ',' << e.env_steps << ',' << static_cast<uint32_t>(r.episodes) << ',' << r.avg_distance
        << ',' << r.avg_object_distance << ',' << r.success_rate << ',' << r.selectivity << ','
        << run_folder::JoinedValues(r.entity_distance) << ',' << run_folder::JoinedValues(r.subgoal_success) << ','
        << r.independent_solved << ',' << r.independent_undone << '\n'
        << std::flush;
}

void CsvSink::Append(const std::string& run_id, const rl::LearnerReport& s, double wall_time) {
  learner_ << Time(wall_time) << ',' << CsvField(run_id) << ',' << s.updates << ',' << s.transitions_inserted << ','
           << s.replay_size << ',' << s.episodes_accepted << ',' << s.episodes_rejected << ',' << s.policy_version
           << ',' << s.q_loss << ',' << s.policy_loss << ',' << s.alpha << ',' << s.entropy << ','
           << s.updates_per_second << ',' << s.inserts_per_second << ',' << s.mean_reward << '\n'
           << std::flush;
}

void CsvSink::Append(const std::string& run_id, const rl::NodeStatus& s, double wall_time,
                     const std::string& state_override) {
  const rl::NodeReport& r = s.report;
  nodes_ << Time(wall_time) << ',' << CsvField(run_id) << ',' << CsvField(s.role) << ',' << s.node_id << ','
         << CsvField(s.host) << ',' << s.pid << ','
         << (state_override.empty() ? rl::NodePhaseName(r.phase) : state_override) << ',' << r.policy_version << ','
         << r.graph_version << ',' << r.steps << ',' << r.dropped << ',' << s.uptime_ms << ',' << CsvField(r.detail)
         << '\n'
         << std::flush;
}

}  // namespace srics::monitor
