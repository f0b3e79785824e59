#pragma once
// The web dashboard of a program that holds a MonitorState (srics run, srics-monitor): an
// HttpServer plus the JSON document rebuilt from the state at most once per publish period.
// The caller's loop calls Update with the state it draws its display from.
//
//   Dashboard dashboard({.port = 8080, .source = "dds"});   // throws BindError
//   std::cout << "dashboard: " << dashboard.url() << "\n";
//   while (...) { monitor.Poll(...); dashboard.Update(monitor.state(), Clock::now(), render); }
//
// Threading: Update, SetRunDir and Json from the thread that owns the state; requests are
// answered on the server's threads from the last published document.

#include <chrono>
#include <optional>
#include <string>

#include "deploy/dashboard/dashboard_json.h"
#include "deploy/dashboard/server.h"
#include "deploy/monitor/display.h"
#include "deploy/monitor/monitor_state.h"

namespace srics::dashboard {

struct DashboardOptions {
  std::string bind = "127.0.0.1";                  // --http-bind
  int port = 0;                                    // --http (0 = any free port)
  std::string source;                              // "dds", "in-process", "run folder"
  std::string run_dir;                             // episode media come from <run_dir>/eval ("" = none yet)
  std::chrono::milliseconds publish_period{1000};  // the JSON is rebuilt at most this often
  int poll_ms = 2000;                              // how often the page asks for it
};

class Dashboard {
 public:
  explicit Dashboard(DashboardOptions options);

  // Rebuilds and publishes the document when the publish period has passed since the last
  // one (or `force`). Returns whether it did.
  bool Update(const monitor::MonitorState& state, monitor::Clock::time_point now, const monitor::RenderOptions& render,
              bool force = false);
  // Whether Update would publish now (for callers whose RenderOptions cost something to build).
  bool Due(monitor::Clock::time_point now) const {
    return !last_publish_ || now - *last_publish_ >= options_.publish_period;
  }
  // The document for this state now (also what `srics-monitor --json` prints).
  std::string Json(const monitor::MonitorState& state, monitor::Clock::time_point now,
                   const monitor::RenderOptions& render) const;
  void SetRunDir(const std::string& dir);

  std::string url() const { return server_.url(); }
  int port() const { return server_.port(); }

 private:
  DashboardOptions options_;
  HttpServer server_;
  std::optional<monitor::Clock::time_point> last_publish_;
};

// The document without a server (srics-monitor --json without --http).
std::string DocumentFor(const monitor::MonitorState& state, monitor::Clock::time_point now,
                        const monitor::RenderOptions& render, const std::string& source, const std::string& run_dir,
                        int poll_ms = 2000);

}  // namespace srics::dashboard
