#pragma once
// Runs the real role processes (srics-graph, srics-learner, srics-actor) on loopback DDS for
// integration tests, and watches the system through the public topics like a monitor.
// Each System gets its own run folder, domain id and run id, so tests never see each other.

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "common/config/config.h"
#include "common/transport/transport.h"
#include "deploy/launcher/child_process.h"

namespace srics::testing {

using namespace std::chrono_literals;
namespace tr = transport;

inline std::string BinaryDir() { return SRICS_BINARY_DIR; }
inline std::string SourceDir() { return SRICS_SOURCE_DIR; }

class System {
 public:
  // `name` makes the run folder and run id unique; extra overrides apply to every process.
  // `config` (relative to the source tree): the run's config, by default the small system.
  explicit System(const std::string& name, std::vector<std::string> overrides = {},
                  const std::string& config = "tests/integration/system-test.yaml") {
    static int counter = 0;
    const int index = counter++;
    run_id_ = name + "-" + std::to_string(getpid()) + "-" + std::to_string(index);
    domain_ = 120 + static_cast<int>((getpid() * 7 + index) % 100);
    run_dir_ = ::testing::TempDir() + "/srics-system/" + run_id_;
    std::filesystem::remove_all(run_dir_);
    std::filesystem::create_directories(run_dir_);
    config_path_ = SourceDir() + "/" + config;
    overrides_ = std::move(overrides);
    overrides_.push_back("transport.domain_id=" + std::to_string(domain_));
    overrides_.push_back("transport.run_id=" + run_id_);
    config_ = config::LoadConfig(config_path_, overrides_);
    participant_ = std::make_unique<tr::Participant>(config_.transport, shutdown_);
    weights_ = std::make_unique<tr::Reader<rl::WeightsUpdate>>(*participant_);
    graphs_ = std::make_unique<tr::Reader<rl::GraphUpdate>>(*participant_);
    stats_ = std::make_unique<tr::Reader<rl::LearnerReport>>(*participant_);
    evals_ = std::make_unique<tr::Reader<rl::EvalReport>>(*participant_);
    status_ = std::make_unique<tr::Reader<rl::NodeStatus>>(*participant_);
  }
  // Stops every role still running (SIGINT, then SIGKILL after 3 s). A role that dies by a
  // signal of its own on the way (a crash while stopping: SIGABRT from malloc, SIGSEGV) fails
  // the test that ran it: such a crash once went unnoticed because tests only checked roles
  // before the teardown.
  ~System() {
    for (auto& [name, child] : children_) {
      if (child.running()) {
        child.Signal(SIGINT);
        const auto status = child.WaitFor(3s);
        if (!status) {
          child.Kill();
        } else if (status->signaled && status->code != SIGINT) {  // SIGINT: stopped before its handler was installed
          ADD_FAILURE() << name << " crashed while stopping: " << status->Describe() << "\n" << Output(name);
        }
      }
    }
  }

  // Starts a role process ("graph", "learner", "actor-K").
  void Start(const std::string& name) {
    std::vector<std::string> argv;
    if (name == "graph")
      argv = {BinaryDir() + "/graph_service/srics-graph"};
    else if (name == "learner")
      argv = {BinaryDir() + "/learner/srics-learner"};
    else
      argv = {BinaryDir() + "/actor/srics-actor", "--id", name.substr(6)};
    argv.push_back(config_path_);
    for (const auto& o : overrides_) {
      argv.push_back("--set");
      argv.push_back(o);
    }
    argv.push_back("--run-dir");
    argv.push_back(run_dir_);
    launcher::SpawnOptions options;
    options.output_file = run_dir_ + "/" + name + ".out";
    children_[name] = launcher::ChildProcess::Spawn(argv, options);
  }
  void StartAll(int actors) {
    Start("graph");
    Start("learner");
    for (int i = 0; i < actors; ++i) Start("actor-" + std::to_string(i));
  }
  launcher::ChildProcess& child(const std::string& name) { return children_.at(name); }
  // Kills a role at once (SIGKILL) and reaps it: a crash, as the other roles see it.
  void Crash(const std::string& name) {
    child(name).Signal(SIGKILL);
    child(name).WaitFor(5s);
  }

  // Reads every topic's news into the latest_* fields; call often.
  void Poll() {
    rl::WeightsUpdate w;
    while (weights_->Take(&w, 0ms) == tr::TakeStatus::kSample) {
      weight_versions.push_back(w.version);
      latest_weights = w.version;
    }
    rl::GraphUpdate g;
    while (graphs_->Take(&g, 0ms) == tr::TakeStatus::kSample) {
      graph = g;
      ++graphs_received;
    }
    rl::LearnerReport s;
    while (stats_->Take(&s, 0ms) == tr::TakeStatus::kSample) stats = s;
    rl::EvalReport e;
    while (evals_->Take(&e, 0ms) == tr::TakeStatus::kSample) evals.push_back(e);
    rl::NodeStatus n;
    while (status_->Take(&n, 0ms) == tr::TakeStatus::kSample) nodes[n.role + "-" + std::to_string(n.node_id)] = n;
  }
  // Polls until `done` holds or `timeout` passes; returns whether it held.
  bool WaitUntil(const std::function<bool()>& done, std::chrono::seconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
      Poll();
      if (done()) return true;
      std::this_thread::sleep_for(50ms);
    }
    Poll();
    return done();
  }
  // Waits for each named role to exit by itself within `timeout`, and expects success (gtest
  // failures name the role and carry its output).
  void ExpectRolesFinish(std::initializer_list<const char*> names, std::chrono::seconds timeout) {
    for (const char* name : names) {
      std::optional<launcher::ExitStatus> status;
      ASSERT_TRUE(WaitUntil([&] { return (status = child(name).Poll()).has_value(); }, timeout))
          << name << " did not finish\n"
          << Output(name);
      EXPECT_TRUE(status->success()) << name << ": " << status->Describe() << "\n" << Output(name);
    }
  }
  // Resident memory of a running child in MB (from /proc), -1 if unknown.
  double ResidentMb(const std::string& name) {
    std::ifstream status("/proc/" + std::to_string(child(name).pid()) + "/status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
    return -1;
  }
  // The tail of a process's output, for failure messages.
  std::string Output(const std::string& name) const {
    std::ifstream in(run_dir_ + "/" + name + ".out");
    std::string text((std::istreambuf_iterator<char>(in)), {});
    return text.size() > 3000 ? text.substr(text.size() - 3000) : text;
  }

  const config::Config& config() const { return config_; }
  const std::string& run_dir() const { return run_dir_; }
  tr::Participant& participant() { return *participant_; }

  // what the system published, as seen by this monitor
  std::vector<uint64_t> weight_versions;
  uint64_t latest_weights = 0;
  std::optional<rl::GraphUpdate> graph;
  int graphs_received = 0;
  std::optional<rl::LearnerReport> stats;
  std::vector<rl::EvalReport> evals;
  std::map<std::string, rl::NodeStatus> nodes;

 private:
  std::string run_id_, run_dir_, config_path_;
  int domain_;
  std::vector<std::string> overrides_;
  config::Config config_;
  tr::Shutdown shutdown_;
  std::unique_ptr<tr::Participant> participant_;
  std::unique_ptr<tr::Reader<rl::WeightsUpdate>> weights_;
  std::unique_ptr<tr::Reader<rl::GraphUpdate>> graphs_;
  std::unique_ptr<tr::Reader<rl::LearnerReport>> stats_;
  std::unique_ptr<tr::Reader<rl::EvalReport>> evals_;
  std::unique_ptr<tr::Reader<rl::NodeStatus>> status_;
  std::map<std::string, launcher::ChildProcess> children_;
};

}  // namespace srics::testing
