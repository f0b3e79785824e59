// ./tests/bench.sh ingest: how many transitions per second the learner process ingests
// (receive, validate, convert, store in the replay; training switched off) from 1, 2, 4 and 8
// actor processes writing as fast as they can, against the bare transport in the same run
// (the same writers to a reader that only takes and validates the samples).
//
//   bench_ingest [--episodes-per-writer N]
//   bench_ingest --writer DOMAIN RUN_ID COUNT ACTOR_ID   (a writer process)

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "actor/env/rearrange_env.h"
#include "actor/explore_episode.h"
#include "common/config/config.h"
#include "common/rl/agent_shape.h"
#include "common/transport/transport.h"
#include "deploy/launcher/child_process.h"
#include "tests/bench/bench_util.h"

namespace {

using namespace srics;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
namespace tr = transport;

const std::string kConfig = std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-3.yaml";

config::Config BenchConfig(int domain, const std::string& run_id) {
  return config::LoadConfig(kConfig, {"transport.domain_id=" + std::to_string(domain), "transport.run_id=" + run_id,
                                      "transport.status_period_s=0.1", "learner.updates_per_step=0", "run.method=smorl",
                                      "run.log_level=warn", "run.total_env_steps=1000000000"});
}

// Writes COUNT training episodes (20 steps of Rearrange 3, recorded once) as fast as it can.
int WriterMain(int domain, const std::string& run_id, uint64_t count, uint32_t actor_id) {
  config::Config config = BenchConfig(domain, run_id);
  auto env = env::MakeRearrangeEnv(config.env);
  nn::Rng rng(actor_id);
  std::vector<rl::Episode> recorded;
  for (int i = 0; recorded.size() < 16; ++i)
    if (auto e = actor::RunExploreEpisode(*env, 20, 100 * actor_id + i, rng)) {
      e->actor_id = actor_id;
      recorded.push_back(std::move(*e));
    }
  tr::Shutdown shutdown;
  tr::Participant participant(config.transport, shutdown);
  tr::Writer<rl::Episode> writer(participant);
  if (!writer.WaitForReaders(1, 20s)) return 3;
  for (uint64_t i = 0; i < count; ++i) {
    rl::Episode& e = recorded[i % recorded.size()];
    e.episode_id = i;
    if (writer.Write(e) != tr::WriteResult::kSent) return 4;
  }
  writer.WaitForAcks(30s);
  return 0;
}

std::vector<launcher::ChildProcess> StartWriters(int writers, int domain, const std::string& run_id,
                                                 uint64_t per_writer) {
  std::vector<launcher::ChildProcess> children;
  char self[4096] = {};
  readlink("/proc/self/exe", self, sizeof self - 1);
  for (int w = 0; w < writers; ++w)
    children.push_back(launcher::ChildProcess::Spawn(
        {self, "--writer", std::to_string(domain), run_id, std::to_string(per_writer), std::to_string(w)}));
  return children;
}

// Transitions per second into the learner process, from the first to the last insertion.
double LearnerIngest(int writers, uint64_t per_writer, int domain) {
  const std::string run_id = "ingest-" + std::to_string(getpid()) + "-" + std::to_string(writers);
  config::Config config = BenchConfig(domain, run_id);
  tr::Shutdown shutdown;
  tr::Participant participant(config.transport, shutdown);
  tr::Reader<srics::rl::LearnerReport> stats(participant);
  auto learner = launcher::ChildProcess::Spawn(
      {std::string(SRICS_BINARY_DIR) + "/learner/srics-learner", kConfig, "--set",
       "transport.domain_id=" + std::to_string(domain), "--set", "transport.run_id=" + run_id, "--set",
       "transport.status_period_s=0.1", "--set", "learner.updates_per_step=0", "--set", "run.method=smorl", "--set",
       "run.log_level=warn", "--set", "run.total_env_steps=1000000000"});
  auto children = StartWriters(writers, domain, run_id, per_writer);
  const uint64_t total = writers * per_writer * 20;
  srics::rl::LearnerReport s;
  uint64_t first_inserted = 0;
  Clock::time_point first, last;
  const auto deadline = Clock::now() + 120s;
  while (Clock::now() < deadline) {
    if (stats.Take(&s, 200ms) != tr::TakeStatus::kSample) continue;
    if (s.transitions_inserted > 0 && first_inserted == 0) {
      first_inserted = s.transitions_inserted;
      first = Clock::now();
    }
    last = Clock::now();
    if (s.transitions_inserted >= total) break;
  }
  for (auto& c : children) c.WaitFor(10s);
  learner.Signal(SIGINT);
  learner.WaitFor(10s);
  if (s.transitions_inserted < total || last <= first) {
    std::cerr << "learner ingested " << s.transitions_inserted << " of " << total << " transitions\n";
    return 0;
  }
  return (s.transitions_inserted - first_inserted) / std::chrono::duration<double>(last - first).count();
}

// The same writers to a bare reader: transport only.
double BareTransport(int writers, uint64_t per_writer, int domain) {
  const std::string run_id = "bare-" + std::to_string(getpid()) + "-" + std::to_string(writers);
  config::Config config = BenchConfig(domain, run_id);
  tr::Shutdown shutdown;
  tr::Participant participant(config.transport, shutdown);
  tr::ReaderOptions options;
  options.episode_limits = rl::EpisodeLimitsFor(config.env);
  tr::Reader<rl::Episode> reader(participant, options);
  auto children = StartWriters(writers, domain, run_id, per_writer);
  const uint64_t total_episodes = writers * per_writer;
  std::vector<rl::Episode> batch;
  uint64_t received = 0;
  Clock::time_point first;
  const auto deadline = Clock::now() + 120s;
  while (received < total_episodes && Clock::now() < deadline) {
    batch.clear();
    const size_t n = reader.TakeMany(&batch, 256, 500ms);
    if (n && received == 0) first = Clock::now();
    received += n;
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - first).count();
  for (auto& c : children) c.WaitFor(10s);
  return received * 20.0 / seconds;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() == 5 && args[0] == "--writer")
    return WriterMain(std::stoi(args[1]), args[2], std::stoull(args[3]), static_cast<uint32_t>(std::stoul(args[4])));
  uint64_t per_writer = 20000;
  if (args.size() == 2 && args[0] == "--episodes-per-writer") per_writer = std::stoull(args[1]);
  const int domain = 40 + static_cast<int>(getpid() % 60);

  std::printf("learner ingest (training off) vs bare transport, Rearrange 3 episodes of 20 steps\n");
  std::printf("(each writer sends %llu episodes; loopback, this machine: 2 cores shared by all processes)\n\n",
              (unsigned long long)per_writer);
  std::printf("%-8s %22s %22s %8s\n", "writers", "learner transitions/s", "bare transitions/s", "ratio");
  std::string json = "{\"bench\":\"ingest\"";
  double first_ratio = 0;
  for (int writers : {1, 2, 4, 8}) {
    const uint64_t n = per_writer / writers;  // the same total at every writer count
    const double bare = BareTransport(writers, n, domain);
    const double learner = LearnerIngest(writers, n, domain);
    const double ratio = bare > 0 ? learner / bare : 0;
    if (writers == 1) first_ratio = ratio;
    std::printf("%-8d %22.0f %22.0f %8.2f\n", writers, learner, bare, ratio);
    json += ",\"learner_tps_" + std::to_string(writers) + "\":" + std::to_string(static_cast<long>(learner)) +
            ",\"bare_tps_" + std::to_string(writers) + "\":" + std::to_string(static_cast<long>(bare));
  }
  std::printf("%s,\"ratio\":%.3f}\n", json.c_str(), first_ratio);
  return 0;
}
