#pragma once
// The monitor's text display: a pure function of the state, the time and a few options, so
// the same screen serves srics-monitor, the launcher's progress display and the tests.

#include <cstdint>
#include <string>
#include <vector>

#include "deploy/monitor/monitor_state.h"

namespace srics::monitor {

// One supervised process, as the launcher sees it (not from DDS: from waitpid).
struct ProcessRow {
  std::string name;   // "actor-1"
  int pid = 0;        // 0 while not running
  std::string state;  // running, restarting in 2.0s, exited, failed
  uint32_t restarts = 0;
  std::string last_exit;  // "exit code 3", "signal 9 (Killed)", "" if it never exited
};

struct RenderOptions {
  std::string title = "srics-monitor";
  std::string run_id;                 // show only this run ("" = every run in the state)
  uint64_t total_env_steps = 0;       // the budget, for the progress bar (0 = unknown)
  double elapsed_s = -1;              // wall time of the run so far (< 0 = not shown)
  double max_wall_minutes = 0;        // shown next to the elapsed time when > 0
  std::vector<ProcessRow> processes;  // the launcher's children (empty for the monitor)
  std::vector<std::string> events;    // the launcher's recent events, oldest first
  size_t history_rows = 5;            // evaluations listed under "history"
};

// Whether options show the run run_id: every run when options.run_id is "".
bool Shown(const std::string& run_id, const RenderOptions& options);
// The runs known from any topic (run views and node statuses) that options show, in name
// order: the runs the display and the dashboard list.
std::vector<std::string> ShownRunIds(const MonitorState& state, const RenderOptions& options);

// The whole screen as text lines ending in '\n' (no terminal control sequences).
std::string Render(const MonitorState& state, Clock::time_point now, const RenderOptions& options);

// One line for logs and non-terminal output: steps, updates, evaluation, graph, node counts.
std::string RenderOneLine(const MonitorState& state, Clock::time_point now, const std::string& run_id,
                          uint64_t total_env_steps);

// The width, in columns, that lines written to the file descriptor fd are clipped to: the
// terminal's own width (TIOCGWINSZ) when fd is a terminal, the COLUMNS variable when the
// terminal does not say; 0 (no clipping) when fd is not a terminal (files, pipes, logs).
// Asked at every redraw, so a resized terminal is followed.
size_t OutputWidth(int fd);
// The rule of OutputWidth: terminal_columns is what TIOCGWINSZ said (0: nothing), columns_env
// the COLUMNS variable (null: unset).
size_t ChooseOutputWidth(bool is_terminal, int terminal_columns, const char* columns_env);

// Every line of text cut to at most `width` characters (UTF-8 code points; a cut line ends in
// '~' in its last column); width 0 leaves the text as it is.
std::string ClipLines(const std::string& text, size_t width);

}  // namespace srics::monitor
