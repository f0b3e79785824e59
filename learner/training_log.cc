#include "learner/training_log.h"

#include "common/files/durable_file.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "common/rl/rewards.h"

namespace srics::learner {
namespace {

constexpr const char* kHeader =
    "wall_time,env_steps,episodes,selectivity,selectivity_episodes,subgoal_distance,subgoal_success,"
    "table_graph_selectivity,table_graph_selectivity_episodes";
// the header before the table-graph columns: its rows are kept, padded with empty columns
constexpr const char* kHeaderWithoutTableGraph =
    "wall_time,env_steps,episodes,selectivity,selectivity_episodes,subgoal_distance,subgoal_success";

double WallTime() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

}  // namespace

double EpisodeSelectivity(const rl::Episode& e, double epsilon) {
  return EpisodeSelectivity(e, epsilon, e.ancestor_mask, e.subgoal_entity);
}

double EpisodeSelectivity(const rl::Episode& e, double epsilon, uint64_t ancestor_mask,
                          const rl::SubgoalUnit& subgoal) {
  const int k = subgoal.entity;
  if (k < 0 || k >= e.layout.num_entities) return -1;
  double sum = 0;
  int steps = 0;
  for (int t = 0; t < e.num_steps; ++t) {
    if (auto m = rl::SelectivityMeasure(e.layout, e.state(t), e.state(t + 1), subgoal, ancestor_mask, epsilon)) {
      sum += *m;
      ++steps;
    }
  }
  return steps ? sum / steps : -1;
}

TrainingLog::TrainingLog(TrainingLogOptions options) : options_(std::move(options)) {
  if (options_.every_env_steps == 0) options_.every_env_steps = 1;
  next_row_at_ = options_.every_env_steps;
  Open();
}

void TrainingLog::Open() {
  if (options_.path.empty()) return;
  std::error_code error;
  const bool fresh = !std::filesystem::exists(options_.path) || std::filesystem::file_size(options_.path, error) == 0;
  out_.open(options_.path, std::ios::app);
  if (!out_) throw std::runtime_error("cannot open " + options_.path);
  out_ << std::setprecision(7);
  if (fresh) out_ << kHeader << '\n' << std::flush;
}

void TrainingLog::ResumeAt(uint64_t env_steps) {
  next_row_at_ = (env_steps / options_.every_env_steps + 1) * options_.every_env_steps;
  ClearWindow();
  if (options_.path.empty()) return;
  // keep the header and the rows up to the checkpoint
  out_.close();
  std::vector<std::string> keep;
  {
    std::ifstream in(options_.path);
    std::string line;
    bool without_table_graph = false;
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      if (keep.empty() || line == kHeader || line == kHeaderWithoutTableGraph) {
        if (keep.empty()) {
          without_table_graph = line == kHeaderWithoutTableGraph;
          keep.push_back(kHeader);
        }
        continue;
      }
      const size_t comma = line.find(',');
      const uint64_t steps = comma == std::string::npos ? 0 : std::strtoull(line.c_str() + comma + 1, nullptr, 10);
      if (steps <= env_steps) keep.push_back(without_table_graph ? line + ",," : line);
    }
  }
  std::string text;
  for (const std::string& line : keep) text += line + '\n';
  files::WriteFileDurably(options_.path, text);
  Open();
}

std::optional<TrainingLog::Figures> TrainingLog::Measure(const rl::Episode& e, int partner) const {
  const int k = e.subgoal_entity;
  if (e.mode != rl::EpisodeMode::kTrain || k < 0 || k >= e.layout.num_entities) return std::nullopt;
  const rl::SubgoalUnit subgoal(k, partner >= 0 && partner < e.layout.num_entities ? partner : -1);
  if (e.goal.size() != 2 * static_cast<size_t>(subgoal.size())) return std::nullopt;
  // the pair's members are its own motion, not its ancestors'
  Figures figures{EpisodeSelectivity(e, options_.epsilon, e.ancestor_mask & ~subgoal.bits(), subgoal),
                  rl::DistanceToSubgoal(e.layout, e.state(e.num_steps), subgoal, e.goal.data()).max};
  if (options_.table_graph && e.entity_kinds.size() == static_cast<size_t>(e.layout.num_entities)) {
    // the table's ancestor sets for the objects this episode presents; kinds the catalogue does
    // not have leave it undefined (the learner refuses such an episode and never counts it)
    try {
      const rl::SubgoalStructure table = rl::CatalogueSubgoals{options_.table_graph}.For(e.entity_kinds);
      if (k < table.num_entities())
        figures.table_graph_selectivity = EpisodeSelectivity(e, options_.epsilon, table.AncestorsOf(subgoal), subgoal);
    } catch (const std::invalid_argument&) {
    }
  }
  return figures;
}

void TrainingLog::ClearWindow() {
  episodes_ = selectivity_episodes_ = successes_ = table_graph_episodes_ = 0;
  selectivity_sum_ = distance_sum_ = table_graph_sum_ = 0;
}

void TrainingLog::Add(const Figures& f) {
  ++episodes_;
  if (f.selectivity >= 0) {
    selectivity_sum_ += f.selectivity;
    ++selectivity_episodes_;
  }
  distance_sum_ += f.subgoal_distance;
  if (f.subgoal_distance < options_.success_threshold) ++successes_;
  if (f.table_graph_selectivity >= 0) {
    table_graph_sum_ += f.table_graph_selectivity;
    ++table_graph_episodes_;
  }
}

void TrainingLog::Advance(uint64_t env_steps, bool force) {
  if (env_steps < next_row_at_ && !force) return;
  if (episodes_ > 0 && out_.is_open()) {
    char wall[32];
    std::snprintf(wall, sizeof wall, "%.3f", WallTime());
    out_ << wall << ',' << env_steps << ',' << episodes_ << ',' << mean_selectivity() << ',' << selectivity_episodes_
         << ',' << distance_sum_ / episodes_ << ',' << static_cast<double>(successes_) / episodes_ << ',';
    if (options_.table_graph) out_ << (table_graph_episodes_ ? table_graph_sum_ / table_graph_episodes_ : 0.0);
    out_ << ',';
    if (options_.table_graph) out_ << table_graph_episodes_;
    out_ << '\n' << std::flush;
  }
  ClearWindow();
  while (next_row_at_ <= env_steps) next_row_at_ += options_.every_env_steps;
}

}  // namespace srics::learner
