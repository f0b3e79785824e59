#include "deploy/launcher/run_session.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <spdlog/sinks/sink.h>
#include <spdlog/spdlog.h>

#include "common/logging/logging.h"
#include "deploy/analysis/gnuplot.h"
#include "deploy/launcher/run_folder.h"
#include "deploy/run_folder/outcome.h"

namespace srics::launcher {

namespace mon = srics::monitor;
namespace fs = std::filesystem;
using SteadyClock = std::chrono::steady_clock;

std::string ClockText(double seconds) {
  char buffer[32];
  const auto s = static_cast<int64_t>(seconds);
  std::snprintf(buffer, sizeof buffer, "%02" PRId64 ":%02" PRId64 ":%02" PRId64, s / 3600, s / 60 % 60, s % 60);
  return buffer;
}

std::string WallLimitReason(const config::Config& config, double elapsed_s) {
  if (config.run.max_wall_minutes <= 0 || elapsed_s < config.run.max_wall_minutes * 60.0) return "";
  char text[96];
  std::snprintf(text, sizeof text, "wall-clock limit of %g minutes reached", config.run.max_wall_minutes);
  return text;
}

namespace {

// This process's CPU time and that of the children it has waited for (the role processes, once
// stopped), so outcome.yaml says what the launch cost in either kind of run.
double LaunchCpuSeconds() {
  double seconds = 0;
  for (int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage usage{};
    if (getrusage(who, &usage) != 0) return -1;
    seconds += usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  }
  return seconds;
}

std::unique_ptr<dashboard::Dashboard> ServeDashboard(const LaunchOptions& options) {
  if (options.http_port < 0) return nullptr;
  return std::make_unique<dashboard::Dashboard>(dashboard::DashboardOptions{
      .bind = options.http_bind, .port = options.http_port, .source = options.in_process ? "in-process" : "dds"});
}

}  // namespace

RunSession::RunSession(const LaunchOptions& options, const config::Config& config)
    : config_(config),
      dashboard_(ServeDashboard(options)),
      dir_(PrepareRunFolder(config, options.run_dir)),
      label_(options.label),
      display_(options.display) {
  run_folder::RemoveRunOutcome(dir_);  // the run goes on: no longer ended
  if (display_ == DisplayMode::kAuto) display_ = isatty(STDOUT_FILENO) ? DisplayMode::kLive : DisplayMode::kPlain;
  auto logger = logging::SetUpLogger("launcher", {.level = config.run.log_level, .file = dir_ + "/logs/launcher.log"});
  if (display_ == DisplayMode::kLive) logger->sinks().front()->set_level(spdlog::level::off);
  logger->flush_on(spdlog::level::info);
  std::cout << "srics run: run folder " << dir_ << "\n" << std::flush;
  if (dashboard_) {
    dashboard_->SetRunDir(dir_);
    std::cout << "srics run: dashboard on " << dashboard_->url() << "\n" << std::flush;
    spdlog::info("dashboard on {}", dashboard_->url());
  }
  spdlog::info("run folder {}, config {}, {} actors{}", dir_, options.config_file, config.actors.count,
               options.in_process ? ", in process" : "");
  start_ = next_draw_ = SteadyClock::now();
  next_line_ = start_ + std::chrono::seconds(10);
  best_ = std::make_unique<BestPolicy>(config, dir_);
}

void RunSession::OnWeights(uint64_t version, uint64_t update_count, const std::string& architecture,
                           const std::vector<float>& parameters) {
  best_->OnWeights(version, update_count, architecture, parameters);
}

void RunSession::OnEval(uint64_t policy_version, uint64_t env_steps, double avg_distance) {
  try {
    if (const auto best = best_->OnEval(policy_version, env_steps, avg_distance)) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "best evaluation so far: avg distance %.4f (policy v%llu, %llu env steps): best.srics",
                    best->avg_distance, static_cast<unsigned long long>(best->policy_version),
                    static_cast<unsigned long long>(best->env_steps));
      Event(text);
    }
  } catch (const std::exception& e) {
    Event(std::string("best.srics not written: ") + e.what());
  }
}

double RunSession::elapsed_s() const { return std::chrono::duration<double>(SteadyClock::now() - start_).count(); }

void RunSession::Remember(const std::string& text) {
  events_.push_back("[" + ClockText(elapsed_s()) + "] " + text);
  if (events_.size() > 8) events_.pop_front();
}

void RunSession::Event(const std::string& text) {
  spdlog::info("{}", text);
  Remember(text);
}

void RunSession::Note(const std::string& text) { Remember(text); }

mon::RenderOptions RunSession::Render(std::vector<mon::ProcessRow> rows) const {
  mon::RenderOptions render;
  render.title = "srics run  " + (label_.empty() ? "" : label_ + "  ") + dir_ + "  (Ctrl-C stops)";
  render.run_id = config_.transport.run_id;
  render.total_env_steps = config_.run.total_env_steps;
  render.max_wall_minutes = config_.run.max_wall_minutes;
  render.elapsed_s = elapsed_s();
  render.processes = std::move(rows);
  render.events.assign(events_.begin(), events_.end());
  return render;
}

void RunSession::Show(const mon::MonitorState& state, std::vector<mon::ProcessRow> rows, uint32_t restarts) {
  const auto now = SteadyClock::now();
  if (dashboard_ && dashboard_->Due(now)) dashboard_->Update(state, now, Render(rows), /*force=*/true);
  // lines clipped to the terminal's width (not in files and pipes)
  if (display_ == DisplayMode::kLive && now >= next_draw_) {
    next_draw_ = now + std::chrono::seconds(1);
    mon::RenderOptions render = Render(std::move(rows));
    if (dashboard_) render.title += "  dashboard " + dashboard_->url();  // the screen hides the printed URL
    std::cout << "\033[H\033[2J"
              << mon::ClipLines(mon::Render(state, mon::Clock::now(), render), mon::OutputWidth(STDOUT_FILENO))
              << std::flush;
  } else if (display_ == DisplayMode::kPlain && now >= next_line_) {
    next_line_ = now + std::chrono::seconds(10);
    const std::string line =
        "[" + ClockText(elapsed_s()) + "] " + (label_.empty() ? "" : label_ + " ") +
        mon::RenderOneLine(state, mon::Clock::now(), config_.transport.run_id, config_.run.total_env_steps) +
        "  restarts " + std::to_string(restarts);
    std::cout << mon::ClipLines(line, mon::OutputWidth(STDOUT_FILENO)) << std::endl;
  }
}

int RunSession::Finish(const mon::MonitorState& state, std::vector<mon::ProcessRow> rows, const std::string& reason,
                       int exit_code, bool clean, uint32_t restarts) {
  std::string plot_error;
  const std::string title =
      config::MethodName(config_.run.method) + std::string(" - ") + fs::path(dir_).filename().string();
  if (!analysis::PlotEvalCurves(dir_, title, &plot_error)) Event("no learning-curve plot: " + plot_error);

  mon::RenderOptions render = Render(std::move(rows));
  render.title = "srics run  " + dir_ + "  finished: " + reason;
  const std::string summary = mon::Render(state, mon::Clock::now(), render);
  std::ofstream(dir_ + "/summary.txt") << summary;
  if (dashboard_) dashboard_->Update(state, mon::Clock::now(), render, /*force=*/true);

  std::string files;
  for (const char* name : {"config.yaml", "resolved-config.yaml", "eval.csv", "learner.csv", "train.csv", "nodes.csv",
                           "curve.png", "subgoal_success.png", "graph.json", "graph.png", "checkpoint.srics",
                           "best.srics", "summary.txt", "outcome.yaml", "logs"})
    if (fs::exists(fs::path(dir_) / name)) files += std::string(files.empty() ? "" : ", ") + name;
  const char* outcome = exit_code == kExitDone ? "finished" : exit_code == kExitInterrupted ? "interrupted" : "FAILED";
  try {
    run_folder::WriteRunOutcome(dir_, {exit_code == kExitDone          ? "finished"
                                       : exit_code == kExitInterrupted ? "interrupted"
                                                                       : "failed",
                                       exit_code, reason, LaunchCpuSeconds()});
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
  }
  std::cout << (display_ == DisplayMode::kLive ? "\033[H\033[2J" : "\n")
            << mon::ClipLines(summary, mon::OutputWidth(STDOUT_FILENO)) << "\n"
            << "run " << outcome << ": " << reason << (clean ? "" : " (some processes had to be killed)")
            << "; restarts " << restarts << "\nrun folder " << dir_ << ": " << files << "\n"
            << std::flush;
  spdlog::info("done: {} (exit code {}), files: {}", reason, exit_code, files);
  return exit_code;
}

}  // namespace srics::launcher
