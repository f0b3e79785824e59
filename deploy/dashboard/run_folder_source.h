#pragma once
// A run folder as the dashboard and the monitor see it: eval.csv, learner.csv and nodes.csv
// (written by the launcher's or a monitor's CsvSink, columns in deploy/run_folder/schema.h),
// graph.json (the graph service), config.yaml (the budget, the liveliness settings) and
// outcome.yaml (how the run ended, in the title) folded
// into the same MonitorState a DDS monitor builds from samples. Works on a finished folder and
// on one whose run is still going (Refresh re-reads what changed).
//
//   RunFolderSource folder("runs/default-20261201-183434");
//   folder.Refresh(Clock::now());
//   std::string text = monitor::Render(folder.state(), Clock::now(), folder.render_options());
//
// Rows are applied in wall-time order across the three files, each at the steady-clock time
// it had (now minus its age), so ages, health and rates read as they did in the run. The
// learner's training env steps (not a learner.csv column) come from its nodes.csv rows.
// Threading: one thread.

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "deploy/dashboard/episode_media.h"
#include "deploy/monitor/display.h"
#include "deploy/monitor/monitor_state.h"

namespace srics::dashboard {

class RunFolderSource {
 public:
  // Throws std::invalid_argument when `dir` is not a folder or holds none of eval.csv,
  // learner.csv, nodes.csv, config.yaml.
  explicit RunFolderSource(std::string dir);

  // Re-reads the folder when a file changed (size or time) since the last call; returns
  // whether the state was rebuilt. A malformed row is skipped and counted; an unreadable
  // config.yaml or graph.json leaves what they would add out. Never throws.
  bool Refresh(monitor::Clock::time_point now);

  const monitor::MonitorState& state() const { return state_; }
  // Title, budget and wall-clock limit for Render and DashboardJson.
  const monitor::RenderOptions& render_options() const { return render_; }
  const std::optional<EpisodeMedia>& episode() const { return episode_; }
  const std::string& dir() const { return dir_; }
  uint64_t skipped_rows() const { return skipped_rows_; }

 private:
  void Rebuild(monitor::Clock::time_point now);

  std::string dir_;
  monitor::MonitorState state_;
  monitor::RenderOptions render_;
  std::optional<EpisodeMedia> episode_;
  std::map<std::string, std::pair<uintmax_t, std::filesystem::file_time_type>> seen_;  // file -> size, time
  uint64_t skipped_rows_ = 0;
};

}  // namespace srics::dashboard
