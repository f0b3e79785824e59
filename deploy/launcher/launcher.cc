#include "deploy/launcher/launcher.h"

#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <set>

#include <spdlog/sinks/sink.h>

#include "actor/actor_loop.h"
#include "common/config/config.h"
#include "common/logging/logging.h"
#include "common/process/role_startup.h"
#include "common/rl/agent_shape.h"
#include "common/transport/transport.h"
#include "deploy/dashboard/server.h"
#include "deploy/launcher/in_process_run.h"
#include "deploy/launcher/run_folder.h"
#include "deploy/launcher/run_guard.h"
#include "deploy/launcher/run_session.h"
#include "deploy/launcher/stall_watch.h"
#include "deploy/monitor/display.h"
#include "deploy/monitor/monitor.h"

namespace srics::launcher {

namespace tr = srics::transport;
namespace mon = srics::monitor;
namespace fs = std::filesystem;

namespace {

// The launcher's view of its children for the display.
std::vector<mon::ProcessRow> ProcessRows(const Supervisor& supervisor, SteadyClock::time_point now) {
  std::vector<mon::ProcessRow> rows;
  for (size_t i = 0; i < supervisor.size(); ++i) {
    const ChildStatus& s = supervisor.status(i);
    mon::ProcessRow row;
    row.name = s.name;
    row.pid = s.pid;
    row.state = ChildPhaseName(s.phase);
    if (s.phase == ChildPhase::kWaitingToRestart) {
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "restarting in %.1fs",
                    std::max(0.0, std::chrono::duration<double>(s.restart_at - now).count()));
      row.state = buffer;
    }
    row.restarts = s.restarts;
    if (s.last_exit) row.last_exit = s.last_exit->Describe();
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

namespace {

// The role processes of this host under a supervisor.
struct Roles {
  std::optional<size_t> graph, learner;
  std::vector<size_t> actors;
};

Roles AddRoles(Supervisor* supervisor, const LaunchOptions& options, const RoleShare& share, const std::string& dir) {
  auto argv = [&](const std::string& bin, std::vector<std::string> extra) {
    std::vector<std::string> v = {bin, dir + "/config.yaml", "--run-dir", dir};
    v.insert(v.end(), extra.begin(), extra.end());
    return v;
  };
  // a role that exits with 2 (config) or 65 (unusable state on disk) fails the run at once
  const std::vector<int> finals = {kExitUsage, kExitUnusableState};
  // the graph service and the learner: one each, restarted up to max_restarts_service times
  auto service = [&](const std::string& name, const std::string& program, const std::string& subdir) {
    return supervisor->Add({.name = name,
                            .argv = argv(FindProgram(program, subdir, options.bin_dir), {}),
                            .output_file = dir + "/logs/" + name + ".out",
                            .max_restarts = options.max_restarts_service,
                            .final_exit_codes = finals});
  };
  Roles roles;
  if (share.graph) roles.graph = service("graph", "srics-graph", "graph_service");
  if (share.learner) roles.learner = service("learner", "srics-learner", "learner");
  if (!share.actor_ids.empty()) {
    const std::string actor_bin = FindProgram("srics-actor", "actor", options.bin_dir);
    for (int k : share.actor_ids)
      roles.actors.push_back(supervisor->Add({.name = "actor-" + std::to_string(k),
                                              .argv = argv(actor_bin, {"--id", std::to_string(k)}),
                                              .output_file = dir + "/logs/actor-" + std::to_string(k) + ".out",
                                              .final_exit_codes = finals}));
  }
  return roles;
}

// Why the run ends now (empty: it goes on), from the children's phases and the clock.
struct Ending {
  std::string reason;
  int exit_code = kExitDone;
};

class EndWatch {
 public:
  EndWatch(const LaunchOptions& options, const config::Config& config, const Roles& roles)
      : options_(options), config_(config), roles_(roles) {}

  Ending Check(Supervisor& supervisor, RunSession& session, const monitor::MonitorState& state) {
    for (size_t i : supervisor.Tick()) {
      const ChildStatus& s = supervisor.status(i);
      if (i == roles_.learner && s.phase == ChildPhase::kFinished) {
        learner_done_ = SteadyClock::now();
        session.Event("the learner finished its budget; waiting for the actors' final evaluation");
      } else if ((i == roles_.learner || i == roles_.graph) && s.phase == ChildPhase::kFailed) {
        return {s.name + " failed for good (" + (s.last_exit ? s.last_exit->Describe() : "?") + ")", kExitFailed};
      }
    }
    // a share without the learner: its stats say when the budget is done
    if (!roles_.learner && !learner_done_ && BudgetDone(state)) {
      learner_done_ = SteadyClock::now();
      session.Event("the learner (on another host) finished its budget");
    }
    bool actors_down = true, actor_failed = false;
    for (size_t i : roles_.actors) {
      const ChildPhase phase = supervisor.status(i).phase;
      actors_down &= phase != ChildPhase::kRunning && phase != ChildPhase::kWaitingToRestart;
      actor_failed |= phase == ChildPhase::kFailed;
    }
    const auto now = SteadyClock::now();
    const auto grace = std::chrono::duration<double>(options_.final_eval_grace_s);
    if (actors_down && !actors_down_at_) actors_down_at_ = now;
    if (learner_done_ && actors_down)
      return actor_failed ? Ending{"the budget is done, but actors failed", kExitFailed} : Ending{"the budget is done"};
    if (learner_done_ && now - *learner_done_ >= grace)
      return {"the budget is done (actors did not finish within the grace period)"};
    if (!learner_done_ && !roles_.actors.empty() && actors_down && !roles_.learner && !actor_failed)
      return {"the budget is done (every actor of this host finished)"};
    if (!learner_done_ && !roles_.actors.empty() && actors_down && now - *actors_down_at_ >= grace)
      return {"every actor ended but the learner did not finish", kExitFailed};
    return {WallLimitReason(config_, session.elapsed_s())};
  }

 private:
  // The run's learner stats say its budget is done.
  bool BudgetDone(const monitor::MonitorState& state) const {
    const auto it = state.runs.find(config_.transport.run_id);
    if (it == state.runs.end()) return false;
    const uint64_t budget = monitor::BudgetEnvSteps(it->second);
    return budget > 0 && monitor::EnvSteps(it->second) >= budget;
  }

  const LaunchOptions& options_;
  const config::Config& config_;
  const Roles& roles_;
  std::optional<SteadyClock::time_point> learner_done_;    // the learner exited with 0
  std::optional<SteadyClock::time_point> actors_down_at_;  // no actor running or restarting
};

// `participant` and `guard` are this launcher's (Run made them and checked that no other run
// of this run id is live).
int RunProcesses(const LaunchOptions& options, const config::Config& config, tr::Participant& participant,
                 RunGuard& guard) {
  const RoleShare share = ShareOf(options, config);
  RunSession session(options, config);
  const std::string& dir = session.dir();
  SeedGraphFile(config, dir);  // a given graph is re-published by srics-graph
  // what the processes publish, to the display and to eval.csv, learner.csv, nodes.csv
  mon::MonitorOptions monitor_options{.all_runs = false, .weights = true, .csv_dir = dir, .csv_node_statuses = true};
  // the run's own learner and graph only: a stray sample never reaches learner.csv or the display
  monitor_options.budget_env_steps = config.run.total_env_steps;
  const rl::RunShape shape = rl::RunShapeFor(config);
  monitor_options.num_entities = shape.entities();  // as the learner
  // the passive baseline is played here, not taken from the wire: a stranger's policy-v0
  // EvalResult that disagrees is refused (issue 39)
  monitor_options.passive_baseline = [&]() -> std::optional<rl::EvaluationSummary> {
    try {
      const actor::ActorOptions actor = actor::ActorOptionsFor(config, shape, 0);
      const auto start = SteadyClock::now();
      rl::EvaluationSummary baseline = actor::PlayPassiveBaseline(actor);
      char text[200];
      std::snprintf(text, sizeof text,
                    "passive baseline played here to check the actors' (%d episodes in %.1f s): avg object "
                    "distance %.4f, avg distance %.4f",
                    baseline.episodes, std::chrono::duration<double>(SteadyClock::now() - start).count(),
                    baseline.avg_object_distance, baseline.avg_distance);
      session.Event(text);
      return baseline;
    } catch (const std::exception& e) {
      session.Event(std::string("passive baseline not played (the actors' is taken as it comes): ") + e.what());
      return std::nullopt;
    }
  };
  monitor_options.on_eval = [&](const rl::EvalReport& e) {
    session.OnEval(e.policy_version, e.env_steps, e.summary.avg_distance);
  };
  monitor_options.on_weights = [&](const rl::WeightsUpdate& w) {
    session.OnWeights(w.version, w.update_count, w.architecture, w.parameters);
  };
  // a later launcher of this run id is refused (it leaves); one that came first (heard only
  // now: a network that joined late) ends this run
  std::set<std::string> refused_launchers;
  std::optional<Judgement> came_first;
  monitor_options.accept_node = [&](const rl::NodeStatus& status) {
    const Judgement judgement = Judge(guard.self(), status, /*roles_started=*/true);
    if (judgement.verdict == Verdict::kNotInTheWay) return true;
    if (judgement.verdict == Verdict::kWasFirst) {
      if (!came_first) came_first = judgement;
    } else if (refused_launchers.insert(judgement.who).second) {
      session.Event("a second launcher of run id " + config.transport.run_id + " came after this one (" +
                    judgement.who + "); it leaves, and its statuses are not this run's");
    }
    return false;
  };
  mon::Monitor monitor(participant, monitor_options);

  SupervisorOptions supervisor_options;
  supervisor_options.backoff = options.backoff;
  supervisor_options.stop_timeout = std::chrono::milliseconds(static_cast<int64_t>(options.stop_timeout_s * 1000));
  supervisor_options.on_event = [&](const std::string& text) { session.Event(text); };
  Supervisor supervisor(supervisor_options);
  Roles roles;
  try {
    roles = AddRoles(&supervisor, options, share, dir);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    std::cerr << "srics run: " << e.what() << "\n";
    return kExitFailed;
  }
  try {
    supervisor.StartAll();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    std::cerr << "srics run: " << e.what() << "\n";
    return kExitFailed;
  }

  EndWatch watch(options, config, roles);
  // this host's roles only (with --roles, a share): the actors' node ids are their actor ids
  std::vector<WatchedNode> watched;
  if (roles.graph) watched.push_back({*roles.graph, "graph", 0});
  if (roles.learner) watched.push_back({*roles.learner, "learner", 0});
  for (size_t k = 0; k < roles.actors.size(); ++k)
    watched.push_back({roles.actors[k], "actor", static_cast<uint32_t>(share.actor_ids[k])});
  StallWatch stalls(std::chrono::milliseconds(static_cast<int64_t>(config.transport.stalled_node_restart_s * 1000)),
                    config.transport.run_id, std::move(watched));
  Ending ending;
  const auto status_period = std::chrono::milliseconds(static_cast<int64_t>(config.transport.status_period_s * 1000));
  auto next_status = SteadyClock::now();
  while (ending.reason.empty()) {
    if (participant.shutdown_requested()) {
      ending = {"interrupted", kExitInterrupted};
      break;
    }
    if (SteadyClock::now() >= next_status) {
      guard.Publish(rl::NodePhase::kTraining);
      next_status = SteadyClock::now() + status_period;
    }
    monitor.Poll(std::chrono::milliseconds(200));
    if (came_first) {
      ending = {SecondRunMessage(config.transport.run_id, config.transport.domain_id, *came_first), kExitUsage};
      break;
    }
    for (const std::string& text : monitor.TakeNodeEvents()) session.Note(text);  // the monitor logged it
    ending = watch.Check(supervisor, session, monitor.state());
    for (const auto& [child, why] : stalls.Check(supervisor, monitor.state(), SteadyClock::now()))
      supervisor.Kill(child, why);
    if (ending.reason.empty())
      session.Show(monitor.state(), ProcessRows(supervisor, SteadyClock::now()), supervisor.total_restarts());
  }
  session.Event("stopping: " + ending.reason);
  guard.Publish(rl::NodePhase::kStopping);
  const bool clean = supervisor.StopAll();
  monitor.Poll(std::chrono::milliseconds(0));  // what the roles said last
  return session.Finish(monitor.state(), ProcessRows(supervisor, SteadyClock::now()), ending.reason, ending.exit_code,
                        clean, supervisor.total_restarts());
}

}  // namespace

RoleShare ShareOf(const LaunchOptions& options, const config::Config& config) {
  RoleShare share;
  const auto has = [&](const char* role) {
    return options.roles.empty() || std::find(options.roles.begin(), options.roles.end(), role) != options.roles.end();
  };
  share.graph = has("graph");
  share.learner = has("learner");
  if (has("actor")) {
    share.actor_ids = options.actor_ids;
    if (share.actor_ids.empty())
      for (int k = 0; k < config.actors.count; ++k) share.actor_ids.push_back(k);
  }
  share.whole_run = options.roles.empty() && options.actor_ids.empty();
  return share;
}

int Run(const LaunchOptions& options) {
  // config first: a bad one stops everything before a folder or a process exists
  // a continued run keeps the defaults it started with (run_folder.h)
  const std::vector<std::string> given = WithEarlierDefaults(options.run_dir, options.overrides);
  config::Config config = config::LoadConfig(options.config_file, given);
  if (!ShareOf(options, config).whole_run) {
    if (options.in_process)
      throw std::invalid_argument("--roles, --ids: not with --in-process (one process runs every role)");
    if (config.transport.run_id == config::kAutoRunId)
      throw std::invalid_argument(
          "--roles, --ids: a share of a run needs the run's id, the same on every host (e.g. --set "
          "transport.run_id=exp7); transport.run_id 'auto' would pick one per host");
  }
  bool fresh_run_id = false;  // made up here: no other run can have it
  if (config.transport.run_id == config::kAutoRunId) {
    fresh_run_id = !options.in_process &&
                   (options.run_dir.empty() || config::RecordedRunId(options.run_dir + "/config.yaml").empty());
    // this launch's own run id (or the one the folder recorded), written into the run
    // folder's config.yaml with the rest of the effective configuration; in process there is
    // no DDS to share, and a fixed id keeps eval.csv the same from launch to launch
    std::vector<std::string> overrides = given;
    overrides.push_back("transport.run_id=" +
                        (options.in_process ? std::string("in-process") : ChooseRunId(options.run_dir)));
    config = config::LoadConfig(options.config_file, overrides);
  }
  try {
    if (options.in_process) {
      // no DDS: nothing of the run goes over the wire, so no other run can merge with it
      CheckResumedConfig(config, options.run_dir, options.allow_config_change);
      return RunInProcess(options, config);
    }
    // DDS Security: the identity of every process this host starts (with --roles, its share
    // only: a host's keystore copy holds its own identities) is in the keystore before
    // anything starts
    config::SecurityConfig& security = config.transport.security;
    const RoleShare share = ShareOf(options, config);
    if (share.learner) config::CheckKeystore(security, "learner");
    if (share.graph) config::CheckKeystore(security, "graph");
    for (int k : share.actor_ids) config::CheckKeystore(security, "actor-" + std::to_string(k));
    security.identity = config::CheckKeystore(security, "launcher");
    // one run id, one run (run_guard.h): before a role starts or a file is written, this
    // launcher announces itself and leaves (exit 2) if a run of this id is live on the domain;
    // not for a run id made up just now (host, pid and time: nobody else has it)
    tr::Participant participant(config.transport);
    RunGuard guard(participant, ShareOf(options, config));
    if (fresh_run_id) {
      guard.Publish(rl::NodePhase::kStarting);
    } else {
      const std::string taken = guard.CheckAlone(ListenWindow(config.transport));
      if (participant.shutdown_requested()) return kExitInterrupted;
      if (!taken.empty()) {
        std::cerr << "srics run: " << taken << "\n";
        return kExitUsage;
      }
    }
    CheckResumedConfig(config, options.run_dir, options.allow_config_change);
    return RunProcesses(options, config, participant, guard);
  } catch (const dashboard::BindError& e) {
    // thrown before the run folder or any process exists (RunSession binds first)
    std::cerr << "srics run: " << e.what() << "\n";
    return kExitUsage;
  }
}

}  // namespace srics::launcher
