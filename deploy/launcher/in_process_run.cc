#include "deploy/launcher/in_process_run.h"

#include "actor/recording/video_recorder.h"

#include <unistd.h>

#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <spdlog/spdlog.h>

#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "actor/actor_loop.h"
#include "actor/env/random_table.h"
#include "common/process/role_startup.h"
#include "common/profile/phase_clock.h"
#include "common/rl/agent_shape.h"
#include "common/rl/ground_truth.h"
#include "common/rl/seeds.h"
#include "common/transport/shutdown.h"
#include "common/transport/wire.h"
#include "deploy/launcher/run_folder.h"
#include "deploy/launcher/run_session.h"
#include "deploy/monitor/csv_sink.h"
#include "graph_service/service.h"
#include "learner/learner_loop.h"

namespace srics::launcher {

namespace mon = srics::monitor;
namespace tr = srics::transport;

namespace {

// Rounds in a row in which no loop did anything before the run counts as stalled. A round in
// which every loop waits is a bug of the loops' contract (someone must always be able to go on).
constexpr uint64_t kStallRounds = 10000;

// The monitor's view of the bus: the same MonitorState and CSV files a DDS monitor builds.
class MonitorObserver : public links::BusObserver {
 public:
  MonitorObserver(const config::Config& config, const std::string& csv_dir, RunSession* session = nullptr)
      : run_id_(config.transport.run_id), start_(mon::Clock::now()), session_(session) {
    if (!csv_dir.empty()) csv_.emplace(csv_dir);
    char name[256] = {};
    if (gethostname(name, sizeof name - 1) == 0) host_ = name;
  }
  void OnEval(const rl::EvalReport& report) override {
    const rl::EvalReport received = tr::AsReceived(report);
    mon::Apply(&state_, run_id_, received, mon::Clock::now());
    if (csv_) csv_->Append(run_id_, received, mon::WallTimeNow());
    if (session_) session_->OnEval(received.policy_version, received.env_steps, received.summary.avg_distance);
  }
  void OnLearnerStats(const rl::LearnerReport& report) override {
    const rl::LearnerReport received = tr::AsReceived(report);
    mon::Apply(&state_, run_id_, received, mon::Clock::now());
    // the learner reports after every step in process: one CSV row a second, as over DDS
    const auto now = mon::Clock::now();
    if (csv_ &&
        (now - last_stats_row_ >= std::chrono::seconds(1) || report.training_env_steps >= report.budget_env_steps)) {
      csv_->Append(run_id_, received, mon::WallTimeNow());
      last_stats_row_ = now;
    }
  }
  void OnGraph(const rl::GraphUpdate& graph) override {
    mon::Apply(&state_, run_id_, tr::AsReceived(graph), mon::Clock::now());
  }
  void OnWeights(const rl::WeightsUpdate& weights) override {
    mon::Apply(&state_, run_id_, weights, mon::Clock::now());  // keeps only the parameters' number
    if (session_) session_->OnWeights(weights.version, weights.update_count, weights.architecture, weights.parameters);
  }
  void OnStatus(const std::string& role, uint32_t id, const rl::NodeReport& report) override {
    // as the topic carries it: no rejections, the detail within the IDL's bound
    rl::NodeStatus m;
    m.role = role;
    m.node_id = id;
    m.host = host_;
    m.pid = static_cast<int32_t>(getpid());
    m.uptime_ms = static_cast<uint64_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(mon::Clock::now() - start_).count());
    m.report = report;
    m.report.rejections.clear();
    if (m.report.detail.size() > tr::kDetailMaxLength) m.report.detail.resize(tr::kDetailMaxLength);
    mon::Apply(&state_, run_id_, m, mon::Clock::now());
    if (csv_ && mon::Clock::now() - last_status_row_[role + std::to_string(id)] >= std::chrono::seconds(1)) {
      csv_->Append(run_id_, m, mon::WallTimeNow());
      last_status_row_[role + std::to_string(id)] = mon::Clock::now();
    }
  }
  const mon::MonitorState& state() const { return state_; }

 private:
  std::string run_id_;
  std::string host_;
  mon::Clock::time_point start_;
  RunSession* session_;  // null: no run folder (learn-graph)
  std::optional<mon::CsvSink> csv_;
  mon::MonitorState state_;
  mon::Clock::time_point last_stats_row_;
  std::map<std::string, mon::Clock::time_point> last_status_row_;
};

}  // namespace

struct InProcessRun::Loops {
  links::InMemoryBus bus;
  std::unique_ptr<links::EpisodeSource> graph_source;
  std::unique_ptr<links::GraphSink> graph_sink;
  std::unique_ptr<graph_service::GraphService> graph;
  std::unique_ptr<links::LearnerLink> learner_link;
  std::unique_ptr<learner::LearnerLoop> learner;
  std::vector<std::unique_ptr<links::ActorLink>> actor_links;
  std::vector<std::unique_ptr<actor::ActorLoop>> actors;
  std::vector<bool> actor_done;
  bool learner_done = false;

  explicit Loops(links::BusObserver* observer) : bus(observer) {}
};

// The second thread of run.in_process_threads: 2. Runs one learner step each time it is asked
// (Start), the owner waiting for it (Wait) before the bus delivers the round's publications.
class InProcessRun::LearnerThread {
 public:
  explicit LearnerThread(std::function<learner::StepResult()> step)
      : step_(std::move(step)), thread_([this] { Loop(); }) {}
  ~LearnerThread() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      quit_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  LearnerThread(const LearnerThread&) = delete;
  LearnerThread& operator=(const LearnerThread&) = delete;

  void Start() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stepping_ = true;
    }
    cv_.notify_all();
  }
  // The step's result; rethrows what it threw.
  learner::StepResult Wait() {
    std::unique_lock<std::mutex> lock(mu_);
    cv_.wait(lock, [this] { return !stepping_; });
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
    return result_;
  }
  // This thread's phase totals as of its last step (read after Wait).
  profile::Totals phases() const {
    std::lock_guard<std::mutex> lock(mu_);
    return phases_;
  }

 private:
  void Loop() {
    std::unique_lock<std::mutex> lock(mu_);
    while (true) {
      cv_.wait(lock, [this] { return stepping_ || quit_; });
      if (quit_) return;
      lock.unlock();
      learner::StepResult result = learner::StepResult::kIdle;
      std::exception_ptr error;
      try {
        profile::PhaseScope phase(profile::Phase::kLearner);
        result = step_();
      } catch (...) {
        error = std::current_exception();
      }
      const profile::Totals phases = profile::Snapshot();
      lock.lock();
      result_ = result, error_ = error, phases_ = phases;
      stepping_ = false;
      cv_.notify_all();
    }
  }

  std::function<learner::StepResult()> step_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  bool stepping_ = false, quit_ = false;
  learner::StepResult result_ = learner::StepResult::kIdle;
  std::exception_ptr error_;
  profile::Totals phases_{};
  std::thread thread_;  // last: started once the members it uses exist
};

InProcessRun::InProcessRun(const config::Config& config, const std::string& dir, links::BusObserver* observer,
                           InProcessOptions options)
    : loops_(std::make_unique<Loops>(observer)), options_(std::move(options)) {
  Loops& l = *loops_;
  const rl::RunShape shape = rl::RunShapeFor(config);  // the roles' sizes, derived once for all of them
  SeedGraphFile(config, dir);                          // a given graph is re-published by the graph service
  if (rl::UsesGraph(config.run.method) || options_.graph_only) {
    l.graph_source = l.bus.GraphSourceEnd(config.graph.refine_after_publish);
    l.graph_sink = l.bus.GraphSinkEnd();
    const graph_service::ServiceOptions options = graph_service::ServiceOptionsFor(config, shape, dir);
    l.graph = std::make_unique<graph_service::GraphService>(config.graph, options, l.graph_source.get(),
                                                            l.graph_sink.get(), options_.on_graph_progress);
  }
  learner::LearnerLoopOptions learner_options =
      learner::LearnerLoopOptionsFor(config, shape, dir.empty() ? "" : dir + "/checkpoint.srics");
  learner_options.report_period_s = 0;  // actors see exact progress: the run is deterministic
  learner_options.final_weights_grace = std::chrono::milliseconds(0);
  const bool two_threads = config.run.in_process_threads == 2 && !options_.graph_only;
  // with its own thread the learner does, in each round, every update the data of the round
  // before pays for, beside the actors' episodes (a few per round would leave it idle most of the
  // round), but does not run ahead of the ratio into the rate limiter's error buffer until the
  // budget is in: one round stays short, and the actors are never held back
  if (two_threads) {
    learner_options.max_updates_per_step = std::numeric_limits<int>::max();
    learner_options.updates_on_ratio_only = true;
  }
  l.learner_link = l.bus.LearnerEnd();
  if (!options_.graph_only) l.learner = std::make_unique<learner::LearnerLoop>(learner_options, l.learner_link.get());
  l.learner_done = options_.graph_only;
  for (int k = 0; k < config.actors.count; ++k) {
    // a resumed run's actors go on from their next episode ids, as restarted actor processes do
    const uint64_t first_id =
        options_.graph_only ? 0 : process::NextActorFirstEpisodeId(dir, "actor-" + std::to_string(k));
    actor::ActorOptions options = actor::ActorOptionsFor(config, shape, static_cast<uint32_t>(k), first_id);
    options.explore_while_waiting_s = 0;  // nothing is lost in memory: exactly the share
    l.actor_links.push_back(l.bus.ActorEnd(static_cast<uint32_t>(k)));
    l.actors.push_back(std::make_unique<actor::ActorLoop>(options, l.actor_links.back().get()));
    if (!options_.graph_only)
      l.actors.back()->set_eval_recorder(actor::RecorderFor(config, l.actors.back()->environment(), k, dir));
    l.actor_done.push_back(false);
  }
  if (two_threads) learner_thread_ = std::make_unique<LearnerThread>([&l] { return l.learner->Step(); });
}

InProcessRun::~InProcessRun() = default;

profile::Totals InProcessRun::PhaseTotals() const {
  profile::Totals totals = profile::Snapshot();
  if (learner_thread_) {
    const profile::Totals learner = learner_thread_->phases();
    for (size_t p = 0; p < totals.size(); ++p) totals[p] += learner[p];
  }
  return totals;
}

bool InProcessRun::StepActors() {
  Loops& l = *loops_;
  bool worked = false;
  for (size_t k = 0; k < l.actors.size(); ++k) {
    if (l.actor_done[k]) continue;
    profile::PhaseScope phase(profile::Phase::kActing);
    const actor::StepResult r = l.actors[k]->Step();
    worked |= r == actor::StepResult::kWorked;
    l.actor_done[k] = r == actor::StepResult::kDone;
  }
  return worked;
}

const graph_service::GraphService* InProcessRun::graph_service() const { return loops_->graph.get(); }

bool InProcessRun::Round() {
  Loops& l = *loops_;
  ++rounds_;
  bool worked = false;
  if (l.graph) {
    profile::PhaseScope phase(profile::Phase::kGraph);
    worked |= l.graph->Step() == graph_service::StepResult::kWorked;
    if (options_.graph_only && l.graph->published()) return false;
    if (l.graph->progress().phase == graph_service::Progress::Phase::kStopped)
      throw std::runtime_error("the graph service stopped without a graph");
  }
  std::optional<learner::StepResult> learner_step;
  if (learner_thread_ && !l.learner_done) {
    // the learner steps on its thread while the actors step here, neither seeing what the other
    // publishes in this round: the bus delivers it once both are done, in a fixed order
    l.bus.Hold();
    learner_thread_->Start();
    std::exception_ptr actors_error, learner_error, delivery_error;
    try {
      worked |= StepActors();
    } catch (...) {
      actors_error = std::current_exception();
    }
    try {
      learner_step = learner_thread_->Wait();  // the learner is idle again before anything unwinds
    } catch (...) {
      learner_error = std::current_exception();
    }
    try {
      l.bus.Release();
    } catch (...) {
      delivery_error = std::current_exception();
    }
    for (const std::exception_ptr& error : {actors_error, learner_error, delivery_error})  // the first cause
      if (error) std::rethrow_exception(error);
  } else {
    worked |= StepActors();
    if (!l.learner_done) {
      profile::PhaseScope phase(profile::Phase::kLearner);
      learner_step = l.learner->Step();
    }
  }
  if (learner_step) {
    worked |= *learner_step == learner::StepResult::kWorked;
    l.learner_done = *learner_step == learner::StepResult::kDone;
  }
  bool actors_done = true;
  for (bool done : l.actor_done) actors_done &= done;
  if (l.learner_done && actors_done) return false;
  idle_rounds_ = worked ? 0 : idle_rounds_ + 1;
  if (idle_rounds_ >= kStallRounds)
    throw std::runtime_error("the in-process run stalled: no loop made progress for " + std::to_string(kStallRounds) +
                             " rounds (" + std::to_string(l.bus.episodes_pending_learner()) +
                             " episodes pending at the learner)");
  return true;
}

void InProcessRun::Stop() {
  if (loops_->learner) loops_->learner->Finish();
}

namespace {

// With SRICS_PHASES=FILE (tests/bench.sh run-cost): the run's CPU time by phase, a row each
// 1,000 more training env steps: env_steps, the process's CPU seconds, then each phase's
// (profile::Phase order); what no phase holds is the process's time minus their sum.
class PhaseLog {
 public:
  static std::unique_ptr<PhaseLog> FromEnvironment() {
    const char* path = std::getenv("SRICS_PHASES");
    if (!path || !*path) return nullptr;
    profile::Enable();
    return std::unique_ptr<PhaseLog>(new PhaseLog(path));
  }
  void Sample(uint64_t env_steps, const InProcessRun& run) {
    if (env_steps < next_) return;
    next_ = env_steps + 1000;
    out_ << env_steps << ',' << profile::ProcessCpuSeconds();
    for (double seconds : run.PhaseTotals()) out_ << ',' << seconds;
    out_ << '\n' << std::flush;
  }

 private:
  explicit PhaseLog(const std::string& path) : out_(path) {
    if (!out_) throw std::runtime_error("SRICS_PHASES: cannot write " + path);
    out_ << "env_steps,cpu_s";
    for (size_t p = 0; p < profile::kPhases; ++p) out_ << ',' << profile::PhaseName(static_cast<profile::Phase>(p));
    out_ << '\n';
  }
  std::ofstream out_;
  uint64_t next_ = 0;
};

}  // namespace

int RunInProcess(const LaunchOptions& options, const config::Config& config) {
  transport::Shutdown::InstallSignalHandlers();
  const auto& stop = transport::Shutdown::Process().flag();
  RunSession session(options, config);
  MonitorObserver observer(config, session.dir(), &session);
  InProcessRun run(config, session.dir(), &observer);
  const std::unique_ptr<PhaseLog> phases = PhaseLog::FromEnvironment();
  std::string reason;
  int exit_code = kExitDone;
  auto rows = [&](const std::string& state) {
    return std::vector<mon::ProcessRow>{{.name = "in-process", .pid = getpid(), .state = state}};
  };
  try {
    while (reason.empty()) {
      if (!run.Round()) {
        reason = "the budget is done";
      } else if (stop) {
        reason = "interrupted";
        exit_code = kExitInterrupted;
      } else {
        reason = WallLimitReason(config, session.elapsed_s());
      }
      session.Show(observer.state(), rows("running"), 0);
      if (phases)
        for (const auto& [id, view] : observer.state().runs) phases->Sample(mon::EnvSteps(view), run);
    }
    if (exit_code != kExitDone || reason != "the budget is done") run.Stop();
  } catch (const std::exception& e) {
    session.Event(std::string("failed: ") + e.what());
    std::cerr << "srics run: " << e.what() << "\n";
    reason = e.what();
    exit_code = kExitFailed;
  }
  session.Event("stopping: " + reason);
  return session.Finish(observer.state(), rows(exit_code == kExitDone ? "finished" : "stopped"), reason, exit_code,
                        true, 0);
}

int LearnGraph(const LearnGraphOptions& o) {
  std::string env_file = o.env_file;
  const std::string& out_dir = o.out_dir;
  if (o.table_seed) {
    // the table is written as a preset file, so the run and a later rerun read the same file
    const uint64_t seed = *o.table_seed;
    const config::EnvConfig table = env::RandomTable(seed);
    const std::string dir = out_dir.empty() ? std::filesystem::temp_directory_path().string() : out_dir;
    std::filesystem::create_directories(dir);
    env_file = dir + "/env.yaml";
    std::ofstream(env_file) << env::RandomTableYaml(table, seed, rl::DescribeGraph(rl::GroundTruthGraph(table)));
  }
  const config::Config config = config::LoadConfig(env_file, o.overrides);
  const std::string expected = rl::DescribeGraph(rl::GroundTruthGraph(config.env));
  if (o.expected_only) {
    std::printf("%s\n", expected.c_str());
    return kExitDone;
  }
  transport::Shutdown::InstallSignalHandlers();
  const auto& stop = transport::Shutdown::Process().flag();
  InProcessOptions options;
  options.graph_only = true;
  bool printed_onsets = false;
  options.on_graph_progress = [&printed_onsets, &graph = config.graph](const graph_service::Progress& p) {
    if (!printed_onsets && !p.onsets_at_a_distance.empty()) {
      // the data's evidence of ties, before training: which objects ever start moving alone
      std::string counts;
      for (size_t j = 0; j < p.onsets_at_a_distance.size(); ++j)
        counts += " " + std::to_string(j) + ": " + std::to_string(p.onsets_at_a_distance[j]);
      std::printf("onsets at a distance (per entity, nothing in reach: a tie's evidence):%s\n", counts.c_str());
      // by the object moving in that step: i->j counts j's onsets at a distance while i moves
      const size_t n = p.onsets_at_a_distance.size();
      std::string by_mover;
      for (size_t i = 0; i < n && p.onsets_while_moving.size() == n * n; ++i)
        for (size_t j = 0; j < n; ++j)
          if (const int64_t count = p.onsets_while_moving[i * n + j]; count > 0)
            by_mover += " " + std::to_string(i) + "->" + std::to_string(j) + ": " + std::to_string(count);
      std::printf("  ... while another object moves (i->j: j starts while i moves):%s\n",
                  by_mover.empty() ? " none" : by_mover.c_str());
      if (!p.tied_by_evidence.empty()) {
        std::string pairs;
        for (const auto& [i, j] : p.tied_by_evidence) pairs += " " + std::to_string(i) + " <-> " + std::to_string(j);
        std::printf("tied by that evidence (their edges' KL times graph.tie_kl_factor):%s\n", pairs.c_str());
      }
      // what the read-out makes of it (tests/bench/gnn-acceptance/pair_bars.py reads this line)
      if (p.tie_evidence_counted && graph.pair_bars_on() && graph.readout == config::GraphReadout::kMeanWeight)
        std::printf("object pairs' bars: %g for a pair tied by that evidence, %g for any other (the arm's edges %g)\n",
                    graph.tied_pair_threshold, graph.untied_pair_threshold, graph.threshold);
      else
        std::printf("object pairs' bars: none (%s): every edge above %g\n",
                    p.tie_evidence_counted ? "off" : "no tie evidence counted",
                    graph.readout == config::GraphReadout::kCut ? graph.cut_threshold : graph.threshold);
      printed_onsets = true;
    }
    std::printf(
        "[%7.1fs] %-10s episodes %d/%d (dropped %d) updates %lld held-out %.3g (no-motion %.3g) stable %d  %s\n",
        p.elapsed_seconds, graph_service::PhaseName(p.phase), p.episodes, p.target_episodes, p.dropped,
        static_cast<long long>(p.updates), p.held_out_loss, p.held_out_zero_loss, p.stable_evaluations,
        p.graph.c_str());
    // the read-out's score of every edge above 0.01, so a user sees how clear the decision was
    const int n = static_cast<int>(std::sqrt(static_cast<double>(p.edge_scores.size())) + 0.5);
    std::string scores;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (const double v = p.edge_scores[static_cast<size_t>(i) * n + j]; i != j && v > 0.01)
          scores += " " + std::to_string(i) + "->" + std::to_string(j) + " " + std::to_string(v).substr(0, 5);
    if (!scores.empty()) std::printf("           edge scores:%s\n", scores.c_str());
    std::fflush(stdout);
  };
  std::filesystem::create_directories(out_dir);
  InProcessRun run(config, out_dir, nullptr, options);
  while (!stop && run.Round() && !(o.evidence_only && printed_onsets)) {
  }
  if (o.evidence_only) {
    if (!printed_onsets) return kExitInterrupted;
    std::printf("by construction: %s\n", expected.c_str());
    return kExitDone;
  }
  const auto* service = run.graph_service();
  if (!service || !service->published()) return kExitInterrupted;
  const std::string learned = rl::DescribeGraph(service->published()->graph);
  std::printf("published graph version %llu: %s\n", static_cast<unsigned long long>(service->published()->version),
              learned.c_str());
  std::printf("by construction: %s (%s)\n", expected.c_str(), learned == expected ? "same" : "differs");
  return kExitDone;
}

}  // namespace srics::launcher
