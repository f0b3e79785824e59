#include "deploy/dashboard/dashboard.h"

namespace srics::dashboard {

std::string DocumentFor(const monitor::MonitorState& state, monitor::Clock::time_point now,
                        const monitor::RenderOptions& render, const std::string& source, const std::string& run_dir,
                        int poll_ms) {
  JsonContext context;
  context.source = source;
  context.run_dir = run_dir;
  context.poll_ms = poll_ms;
  if (!run_dir.empty()) context.episode = FindLatestEpisode(run_dir);
  return DashboardJson(state, now, render, context);
}

Dashboard::Dashboard(DashboardOptions options)
    : options_(std::move(options)),
      server_({.bind = options_.bind, .port = options_.port, .run_dir = options_.run_dir}) {}

bool Dashboard::Update(const monitor::MonitorState& state, monitor::Clock::time_point now,
                       const monitor::RenderOptions& render, bool force) {
  if (!force && !Due(now)) return false;
  last_publish_ = now;
  server_.Publish(Json(state, now, render));
  return true;
}

std::string Dashboard::Json(const monitor::MonitorState& state, monitor::Clock::time_point now,
                            const monitor::RenderOptions& render) const {
  return DocumentFor(state, now, render, options_.source, options_.run_dir, options_.poll_ms);
}

void Dashboard::SetRunDir(const std::string& dir) {
  options_.run_dir = dir;
  server_.SetRunDir(dir);
}

}  // namespace srics::dashboard
