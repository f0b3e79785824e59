#include "deploy/dashboard/run_folder_watch.h"

#include <unistd.h>

#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

#include "common/cli/exit_codes.h"
#include "common/transport/shutdown.h"
#include "deploy/dashboard/dashboard.h"
#include "deploy/dashboard/run_folder_source.h"
#include "deploy/monitor/display.h"

namespace srics::dashboard {
namespace {

namespace mon = srics::monitor;

// The run the one-line summary is about: the folder's (the one with most evaluations).
std::string MainRun(const mon::MonitorState& state) {
  std::string id;
  size_t most = 0;
  for (const auto& [name, run] : state.runs)
    if (id.empty() || run.evals.size() > most) id = name, most = run.evals.size();
  return id;
}

}  // namespace

int WatchRunFolder(const RunFolderWatch& options) {
  std::optional<RunFolderSource> folder;
  std::unique_ptr<Dashboard> dashboard;
  try {
    folder.emplace(options.run_dir);
    if (options.http_port >= 0) {
      dashboard = std::make_unique<Dashboard>(DashboardOptions{
          .bind = options.http_bind, .port = options.http_port, .source = "run folder", .run_dir = options.run_dir});
      std::cerr << "srics-monitor: dashboard on " << dashboard->url() << std::endl;
    }
  } catch (const std::exception& e) {  // not a run folder, or a port that cannot be served
    std::cerr << "srics-monitor: " << e.what() << "\n";
    return kExitUsage;
  }
  try {
    const bool live = !options.once && !options.json && isatty(STDOUT_FILENO);
    const auto& stop = transport::Shutdown::Process().flag();
    const auto refresh =
        std::chrono::duration_cast<mon::Clock::duration>(std::chrono::duration<double>(options.refresh_s));
    const auto start = mon::Clock::now();
    auto json_line = [&] {
      return DocumentFor(folder->state(), mon::Clock::now(), folder->render_options(), "run folder", options.run_dir);
    };
    auto screen = [&] {
      mon::RenderOptions render = folder->render_options();
      if (dashboard) render.title += "  dashboard " + dashboard->url();  // the refreshing screen hides the printed URL
      // lines clipped to the terminal's width (not in files and pipes), as srics-monitor's display
      return mon::ClipLines(mon::Render(folder->state(), mon::Clock::now(), render), mon::OutputWidth(STDOUT_FILENO));
    };
    folder->Refresh(mon::Clock::now());
    // every refresh period: re-read the folder, publish, draw (a plain line every 10th time)
    uint64_t tick = 0;
    for (auto next = start; !options.once && !stop;) {
      const auto now = mon::Clock::now();
      if (options.for_s > 0 && now - start >= std::chrono::duration<double>(options.for_s)) break;
      if (now < next) {
        std::this_thread::sleep_for(std::min<mon::Clock::duration>(std::chrono::milliseconds(100), next - now));
        continue;
      }
      next = now + refresh;
      folder->Refresh(now);
      if (dashboard) dashboard->Update(folder->state(), now, folder->render_options(), /*force=*/true);
      if (options.json) {
        std::cout << json_line() << std::endl;
      } else if (live) {
        std::cout << "\033[H\033[2J" << screen() << std::flush;
      } else if (tick % 10 == 0) {
        std::cout << mon::ClipLines(mon::RenderOneLine(folder->state(), now, MainRun(folder->state()),
                                                       folder->render_options().total_env_steps),
                                    mon::OutputWidth(STDOUT_FILENO))
                  << std::endl;
      }
      ++tick;
    }
    if (options.json && options.once)
      std::cout << json_line() << std::endl;
    else if (!options.json && (options.once || !live))
      std::cout << screen() << std::flush;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "srics-monitor: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace srics::dashboard
