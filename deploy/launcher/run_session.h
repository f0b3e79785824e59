#pragma once
// What every way of running (`srics run` with processes, `srics run --in-process`) shares:
// the run folder, the launcher's log, the live display or plain progress lines, the events
// list, and the end (plots, summary.txt, the closing lines). The two runners only differ in
// how the roles are wired.

#include <chrono>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "common/config/config.h"
#include "deploy/dashboard/dashboard.h"
#include "deploy/launcher/best_policy.h"
#include "deploy/launcher/launcher.h"
#include "deploy/monitor/display.h"
#include "deploy/monitor/monitor_state.h"

namespace srics::launcher {

class RunSession {
 public:
  // Prepares the run folder (config.yaml, logs/), the log file and the display mode, and
  // says where the run folder is. Throws std::runtime_error.
  // Throws dashboard::BindError when --http's port cannot be listened on.
  RunSession(const LaunchOptions& options, const config::Config& config);

  const std::string& dir() const { return dir_; }
  double elapsed_s() const;
  // Logged and on the display.
  void Event(const std::string& text);
  // On the display only (the monitor has logged it).
  void Note(const std::string& text);
  // Redraws the live display (at most once a second) or prints a plain line (every 10 s),
  // and the web dashboard's document (at most once a second) when it is served.
  void Show(const monitor::MonitorState& state, std::vector<monitor::ProcessRow> rows, uint32_t restarts);
  // What the run published, for best.srics (best_policy.h): weights and evaluations.
  void OnWeights(uint64_t version, uint64_t update_count, const std::string& architecture,
                 const std::vector<float>& parameters);
  void OnEval(uint64_t policy_version, uint64_t env_steps, double avg_distance);

  // Plots the curves, writes summary.txt and outcome.yaml (how the run ended) and prints the
  // closing lines. Returns exit_code.
  int Finish(const monitor::MonitorState& state, std::vector<monitor::ProcessRow> rows, const std::string& reason,
             int exit_code, bool clean, uint32_t restarts);

 private:
  monitor::RenderOptions Render(std::vector<monitor::ProcessRow> rows) const;
  void Remember(const std::string& text);

  const config::Config& config_;
  // --http: listening before the run folder is made (a taken port stops the run before
  // anything exists: BindError from the constructor)
  std::unique_ptr<dashboard::Dashboard> dashboard_;
  std::string dir_;
  std::string label_;
  DisplayMode display_;
  std::chrono::steady_clock::time_point start_, next_draw_, next_line_;
  std::deque<std::string> events_;
  std::unique_ptr<BestPolicy> best_;
};

// "wall-clock limit of 27 minutes reached" once run.max_wall_minutes (> 0) has passed, else "".
std::string WallLimitReason(const config::Config& config, double elapsed_s);

// "00:12:34"
std::string ClockText(double seconds);

}  // namespace srics::launcher
