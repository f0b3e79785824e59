#pragma once
// `srics-monitor --run-dir DIR` without a CONFIG: a run folder's files instead of DDS, with
// the monitor's own outputs: the terminal display (refreshing on a terminal, else a line every
// 10 refresh periods), --json lines, --once, and the web dashboard with --http. The folder is
// re-read when its files change, so a run going on in another process is followed too.

#include <string>

namespace srics::dashboard {

struct RunFolderWatch {
  std::string run_dir;
  int http_port = -1;  // -1: no dashboard; 0: any free port
  std::string http_bind = "127.0.0.1";
  bool json = false;     // the JSON document instead of the display
  bool once = false;     // one display (or JSON line) and exit
  double for_s = 0;      // stop after this long (0: until Ctrl-C)
  double refresh_s = 1;  // how often the folder is re-read and the display redrawn
};

// Runs until Ctrl-C, --for or --once. Returns the exit code: 0, 2 when DIR is not a run
// folder or the port cannot be served (the message on stderr), 1 on another failure.
int WatchRunFolder(const RunFolderWatch& options);

}  // namespace srics::dashboard
