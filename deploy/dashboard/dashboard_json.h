#pragma once
// The dashboard's JSON document: a pure function of the monitor's state (the same MonitorState
// and RenderOptions the terminal display is drawn from), the time and where the run folder
// is. Served at /api/state and printed by `srics-monitor --json`, one object per line.
//
// Top level: schema ("srics-dashboard/1"), title, source, run_dir, poll_ms, wall_time,
// elapsed_s, runs[], nodes[], node_counts, processes[], events[], episode.
// Per run: run_id, env_steps, budget_env_steps, env_steps_per_second and eta_s (null unless
// the learner reported within the state's lost_after), learner,
// learner_history (column arrays: updates, env_steps, q_loss, policy_loss, alpha, entropy,
// mean_reward, updates_per_second, inserts_per_second), passive, latest_eval, evals[] (every
// kept evaluation of a trained policy, oldest first), graph (matrices as rows, edges[]),
// weights. Unknown values are null. deploy/dashboard/README.md lists every field.

#include <optional>
#include <string>

#include "deploy/dashboard/episode_media.h"
#include "deploy/monitor/display.h"
#include "deploy/monitor/monitor_state.h"

namespace srics::dashboard {

struct JsonContext {
  std::string source;                   // "dds", "in-process", "run folder"
  std::string run_dir;                  // "" when unknown (a monitor without a folder)
  int poll_ms = 2000;                   // how often the page asks again
  std::optional<EpisodeMedia> episode;  // the latest recorded episode, if any
};

std::string DashboardJson(const monitor::MonitorState& state, monitor::Clock::time_point now,
                          const monitor::RenderOptions& options, const JsonContext& context);

}  // namespace srics::dashboard
