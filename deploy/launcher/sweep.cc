#include "deploy/launcher/sweep.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "common/config/config.h"
#include "common/transport/shutdown.h"
#include "deploy/launcher/child_process.h"
#include "deploy/launcher/run_folder.h"
#include "deploy/launcher/run_session.h"
#include "deploy/run_folder/outcome.h"

namespace srics::launcher {

namespace fs = std::filesystem;
using SteadyClock = std::chrono::steady_clock;

namespace {

// The manifest: the grid in a canonical form (sorted methods and seeds, overrides in order).
std::string ManifestText(const std::string& config, std::vector<std::string> methods, std::vector<uint64_t> seeds,
                         const std::vector<std::string>& overrides) {
  std::sort(methods.begin(), methods.end());
  std::sort(seeds.begin(), seeds.end());
  std::ostringstream out;
  out << "config: " << run_folder::QuotedString(config) << "\nmethods: [";
  for (size_t i = 0; i < methods.size(); ++i) out << (i ? ", " : "") << methods[i];
  out << "]\nseeds: [";
  for (size_t i = 0; i < seeds.size(); ++i) out << (i ? ", " : "") << seeds[i];
  out << "]\nset: [";
  for (size_t i = 0; i < overrides.size(); ++i) out << (i ? ", " : "") << run_folder::QuotedString(overrides[i]);
  out << "]\n";
  return out.str();
}

std::string LastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  // a live display's escape sequences and over-long lines are cut
  if (last.size() > 160) last = last.substr(0, 160) + "...";
  return last;
}

// The sweep's own log (<sweep>/sweep.log) and console lines.
class SweepLog {
 public:
  explicit SweepLog(const std::string& dir) : file_(dir + "/sweep.log", std::ios::app) {}
  void operator()(const std::string& text) {
    std::cout << "srics sweep: " << text << std::endl;
    file_ << "[" << LocalTime("%Y-%m-%d %H:%M:%S") << "] " << text << std::endl;
  }

 private:
  std::ofstream file_;
};

}  // namespace

SweepPlan PlanSweep(const SweepOptions& options) {
  for (const std::string& o : options.overrides) {
    const std::string key = o.substr(0, o.find('='));
    if (key == "run.method" || key == "run.seed" || key == "run.name")
      throw std::invalid_argument("--set " + key + ": the sweep sets it for each run (use --methods and --seeds)");
  }
  SweepPlan plan;
  plan.config = fs::absolute(options.config_file).lexically_normal().string();
  // the base config decides the default folder (and must load on its own)
  const config::Config base = config::LoadConfig(plan.config, options.overrides);
  const std::string dir =
      options.out_dir.empty() ? base.run.output_dir + "/" + base.run.name + "-sweep" : options.out_dir;
  plan.dir = fs::absolute(dir).lexically_normal().string();
  plan.manifest = ManifestText(plan.config, options.methods, options.seeds, options.overrides);
  std::string launch_id;  // NewRunId(), when a run needs one
  for (const std::string& method : options.methods) {
    for (uint64_t seed : options.seeds) {
      SweepRun run;
      run.method = method;
      run.seed = seed;
      run.name = method + "-seed" + std::to_string(seed);
      run.dir = plan.dir + "/" + run.name;
      run.overrides = options.overrides;
      run.overrides.push_back("run.method=" + method);
      run.overrides.push_back("run.seed=" + std::to_string(seed));
      run.overrides.push_back("run.name=" + run.name);
      // runs of one sweep may share a DDS domain (--parallel): each has its own run id. With
      // transport.run_id: auto, a run keeps the id its folder recorded, else gets this
      // launch's id and its name (two sweeps on one host never share a run id)
      std::string run_id;
      if (base.transport.run_id != config::kAutoRunId) {
        run_id = base.transport.run_id + "-" + run.name;
        if (run_id.size() > 64) run_id = run_id.substr(run_id.size() - 64);
      } else {
        if (launch_id.empty()) launch_id = NewRunId();
        run_id = config::RecordedRunId(run.dir + "/config.yaml");
        if (run_id.empty()) run_id = launch_id + "-" + run.name;
        if (run_id.size() > 64) run_id = launch_id + "-r" + std::to_string(plan.runs.size() + 1);
      }
      run.overrides.push_back("transport.run_id=" + run_id);
      // loading it checks the method name and every value (ConfigError names the key); a
      // resumed run keeps the defaults it started with (run_folder.h: its srics run adds them too)
      const config::Config loaded = config::LoadConfig(plan.config, WithEarlierDefaults(run.dir, run.overrides));
      run.effective_yaml = loaded.effective_yaml;
      run.resolved_yaml = loaded.resolved_yaml;
      plan.runs.push_back(std::move(run));
    }
  }
  return plan;
}

void CheckSweepFolder(const SweepPlan& plan) {
  const std::string manifest_path = plan.dir + "/sweep.yaml";
  if (fs::exists(manifest_path)) {
    const std::string existing = WithoutComments(manifest_path);
    if (existing != plan.manifest)
      throw std::invalid_argument("the sweep folder " + plan.dir + " holds another grid (" +
                                  FirstDifference(existing, plan.manifest) + ");\nits sweep.yaml:\n" + existing +
                                  "this command's grid:\n" + plan.manifest +
                                  "run the folder's own grid to resume it, or choose another --out");
  }
  for (const SweepRun& run : plan.runs) {
    const std::string difference = ConfigChangeSince(run.dir, run.effective_yaml, run.resolved_yaml);
    if (!difference.empty())
      throw std::invalid_argument("the configuration of " + run.dir + " changed since it started (" + difference +
                                  "): a resumed run must go on with the configuration it started with; "
                                  "restore the config file or choose another --out");
  }
  std::error_code error;
  fs::create_directories(plan.dir + "/logs", error);
  if (error) throw std::runtime_error("cannot create the sweep folder " + plan.dir + ": " + error.message());
  if (!fs::exists(manifest_path)) {
    std::ofstream out(manifest_path);
    out << "# srics sweep: the grid of this folder (the same command resumes it; another grid is refused)\n"
        << plan.manifest;
    if (!out) throw std::runtime_error("cannot write " + manifest_path);
  }
}

namespace {

// The sweep's runs as child processes.
class SweepRunner {
 public:
  SweepRunner(const SweepOptions& options, const SweepPlan& plan, SweepLog& log)
      : options_(options), plan_(plan), log_(log) {
    program_ = options.program.empty() ? ExecutableDir() + "/srics" : options.program;
    if (options.program.empty()) {
      std::error_code error;
      const fs::path self = fs::read_symlink("/proc/self/exe", error);
      if (!error) program_ = self.string();
    }
  }

  int Run(const std::atomic<bool>& stop) {
    const size_t total = plan_.runs.size();
    std::vector<size_t> queue;
    for (size_t i = 0; i < total; ++i) {
      if (run_folder::RunFinished(plan_.runs[i].dir)) {
        ++finished_;
        log_("run " + Position(i) + " " + plan_.runs[i].name + ": finished earlier, skipped");
      } else {
        queue.push_back(i);
      }
    }
    std::reverse(queue.begin(), queue.end());  // the grid's order, taken from the back
    auto next_lines = SteadyClock::now() + std::chrono::seconds(10);
    while (!queue.empty() || !running_.empty()) {
      if (stop) return Interrupt();
      while (static_cast<int>(running_.size()) < options_.parallel && !queue.empty()) {
        const size_t i = queue.back();
        queue.pop_back();
        Start(i);
      }
      for (auto it = running_.begin(); it != running_.end();) {
        if (auto status = it->child.Poll()) {
          Ended(*it, *status);
          it = running_.erase(it);
        } else {
          ++it;
        }
      }
      if (options_.parallel > 1 && SteadyClock::now() >= next_lines) {
        next_lines = SteadyClock::now() + std::chrono::seconds(10);
        for (const Running& r : running_)
          std::cout << "  run " << Position(r.index) << " " << plan_.runs[r.index].name << ": "
                    << LastLine(OutputFile(r.index)) << std::endl;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return Summary();
  }

 private:
  struct Running {
    size_t index;
    ChildProcess child;
    SteadyClock::time_point start;
  };

  std::string Position(size_t i) const { return std::to_string(i + 1) + " of " + std::to_string(plan_.runs.size()); }
  std::string OutputFile(size_t i) const { return plan_.dir + "/logs/" + plan_.runs[i].name + ".out"; }

  void Start(size_t i) {
    const SweepRun& run = plan_.runs[i];
    const bool resuming = fs::exists(run.dir + "/config.yaml");
    std::vector<std::string> argv = {program_, "run", plan_.config, "--run-dir", run.dir};
    for (const std::string& o : run.overrides) argv.insert(argv.end(), {"--set", o});
    argv.insert(argv.end(), {"--label", "sweep run " + Position(i) + ": " + run.name});
    if (options_.in_process) argv.push_back("--in-process");
    const bool shared_console = options_.parallel == 1;
    std::string display = "plain";
    if (shared_console) {
      switch (options_.display) {
        case DisplayMode::kAuto: display = "auto"; break;
        case DisplayMode::kLive: display = "live"; break;
        case DisplayMode::kPlain: display = "plain"; break;
        case DisplayMode::kNone: display = "none"; break;
      }
    }
    argv.insert(argv.end(), {"--display", display});
    log_("run " + Position(i) + " " + run.name + ": " +
         (fs::exists(run.dir + "/checkpoint.srics") ? "resuming from its checkpoint"
          : resuming                                ? "resuming (no checkpoint yet)"
                                                    : "starting") +
         (shared_console ? "" : " (output in " + OutputFile(i) + ")"));
    SpawnOptions spawn;
    spawn.output_file = shared_console ? "" : OutputFile(i);
    try {
      running_.push_back({i, ChildProcess::Spawn(argv, spawn), SteadyClock::now()});
    } catch (const std::exception& e) {
      ++failed_;
      log_("run " + Position(i) + " " + run.name + ": cannot start: " + e.what());
    }
  }

  void Ended(const Running& r, const ExitStatus& status) {
    const SweepRun& run = plan_.runs[r.index];
    const double seconds = std::chrono::duration<double>(SteadyClock::now() - r.start).count();
    const std::optional<run_folder::RunOutcome> outcome = run_folder::ReadRunOutcome(run.dir);
    std::string text = "run " + Position(r.index) + " " + run.name + ": ";
    if (outcome && outcome->state == "finished" && status.success()) {
      ++finished_;
      text += "finished (" + outcome->reason + ")";
    } else {
      ++failed_;
      text += (outcome ? outcome->state + " (" + outcome->reason + ", " : std::string("ended without an outcome (")) +
              status.Describe() + ")";
    }
    log_(text + " after " + ClockText(seconds));
  }

  int Interrupt() {
    log_("interrupted: stopping " + std::to_string(running_.size()) + " run(s); each checkpoints");
    for (Running& r : running_) r.child.Signal(SIGINT);
    const auto deadline = SteadyClock::now() + std::chrono::duration<double>(options_.stop_timeout_s);
    for (Running& r : running_) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now());
      std::optional<ExitStatus> status = r.child.WaitFor(std::max(left, std::chrono::milliseconds(0)));
      if (!status) {
        log_("run " + plan_.runs[r.index].name + " did not stop in time: killed");
        status = r.child.Kill();
      }
      const std::optional<run_folder::RunOutcome> outcome = run_folder::ReadRunOutcome(plan_.runs[r.index].dir);
      log_("run " + Position(r.index) + " " + plan_.runs[r.index].name + ": " +
           (outcome ? outcome->state : std::string("stopped")) + " (" + status->Describe() + ")");
    }
    running_.clear();
    log_(std::to_string(finished_) + " of " + std::to_string(plan_.runs.size()) +
         " runs finished; the same command resumes the sweep in " + plan_.dir);
    return kExitInterrupted;
  }

  int Summary() {
    const size_t total = plan_.runs.size();
    log_(std::to_string(finished_) + " of " + std::to_string(total) + " runs finished" +
         (failed_ ? ", " + std::to_string(failed_) + " did not (the same command retries them)" : std::string()) +
         "; sweep folder " + plan_.dir + " (srics compare " + plan_.dir + ")");
    return failed_ ? kExitFailed : kExitDone;
  }

  const SweepOptions& options_;
  const SweepPlan& plan_;
  SweepLog& log_;
  std::string program_;
  std::vector<Running> running_;
  size_t finished_ = 0, failed_ = 0;
};

}  // namespace

int Sweep(const SweepOptions& options) {
  transport::Shutdown::InstallSignalHandlers();
  const SweepPlan plan = PlanSweep(options);  // ConfigError, invalid_argument: exit 2 in main
  CheckSweepFolder(plan);
  SweepLog log(plan.dir);
  log("sweep folder " + plan.dir + ": " + std::to_string(options.methods.size()) + " method(s) x " +
      std::to_string(options.seeds.size()) + " seed(s) = " + std::to_string(plan.runs.size()) + " runs" +
      (options.in_process ? ", in process" : "") +
      (options.parallel > 1 ? ", " + std::to_string(options.parallel) + " at a time" : ""));
  SweepRunner runner(options, plan, log);
  return runner.Run(transport::Shutdown::Process().flag());
}

}  // namespace srics::launcher
