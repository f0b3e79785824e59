// The soak's foreign participant (./tests/bench.sh soak): joins a live run's domain and run id
// and publishes bursts of bad samples on every topic the run reads, with raw writers (no
// checks of its own, envelope stamped as the run's):
//   episodes   a real episode of the run (taken from the episode topic) with a NaN state, a
//              position 1 km away, an action of 1e30, one state missing; one of another
//              layout (test_samples' MakeEpisode); and the real episode itself twice (a
//              replay: the learner must not ingest it again)
//   weights    the run's latest weights (or a test sample) at version 2^62 + burst: one
//              parameter fewer, one of 1e30, one NaN, another architecture
//   graphs     a complete graph of 16 entities at version 2^62 + burst; a test sample graph
//   stats      LearnerStats of a stranger: the run "done" under another budget, done with
//              fewer transitions than steps, 2^62 steps
//   evals      EvalResult with NaN distances, with a huge policy version
//   status     NodeStatus with terminal control characters in every string
// The shared builders are test_samples.h's (as transport_peer and the foreign-samples tests).
//
//   bench_soak RUN_CONFIG BURSTS PERIOD_S
// RUN_CONFIG: the run folder's config.yaml (domain, run id, Cyclone profile, environment).
// Prints one line per burst ("burst N: ... samples, episode template yes/no") and exits 0
// after BURSTS bursts, PERIOD_S seconds apart (the first at once), or on SIGINT/SIGTERM. A
// burst takes about 30 s: each weights, graph and stats sample stands alone for 3 s.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <thread>

#include "common/config/config.h"
#include "common/rl/agent_shape.h"
#include "common/transport/endpoint.h"
#include "common/transport/shutdown.h"
#include "tests/common/transport/test_samples.h"

namespace {

using namespace srics;
using namespace srics::transport;
using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr auto kAlone = std::chrono::seconds(3);

WriterOptions Raw() {
  WriterOptions o;
  o.validate = false;  // stamped (run id, contract, weights checksum) but never checked
  return o;
}

// The newest sample a reader holds, if any arrived within `wait`.
template <typename T>
std::optional<T> Newest(Reader<T>& reader, milliseconds wait) {
  std::optional<T> newest;
  T sample;
  while (reader.Take(&sample, newest ? milliseconds(0) : wait) == TakeStatus::kSample) newest = sample;
  return newest;
}

class Injector {
 public:
  explicit Injector(const config::Config& config)
      : config_(config),
        participant_(config.transport),
        episodes_(participant_, Raw()),
        weights_(participant_, Raw()),
        graphs_(participant_, Raw()),
        stats_(participant_, Raw()),
        evals_(participant_, Raw()),
        status_(participant_, Raw()),
        weights_in_(participant_),
        stats_in_(participant_) {}

  // One burst; returns how many samples were written.
  int Burst(uint64_t n) {
    int written = 0;
    auto send = [&](auto& writer, const auto& sample) {
      if (writer.Write(sample) == WriteResult::kSent) ++written;
    };
    // weights, graphs and stats are keep-last 1: readers see only the newest, so each bad
    // sample stands alone for a while (actors look between episodes)
    auto send_alone = [&](auto& writer, const auto& sample) {
      send(writer, sample);
      std::this_thread::sleep_for(kAlone);
    };
    const uint64_t huge = (uint64_t{1} << 62) + n;

    // episodes: mutations of a real one of the run, another layout, and a replay
    template_episode_ = TakeRunEpisode().value_or(testing::MakeEpisode(n));
    const rl::Episode& real = template_episode_;
    rl::Episode e = real;
    e.states[e.states.size() / 2] = kNaN;
    send(episodes_, e);
    e = real;
    e.states[e.layout.position_offset(e.layout.num_entities - 1)] = 1000.0f;
    send(episodes_, e);
    e = real;
    e.actions[0] = 1e30f;
    send(episodes_, e);
    e = real;
    e.states.pop_back();
    send(episodes_, e);
    send(episodes_, testing::MakeEpisode(n));
    send(episodes_, real);  // replayed twice: at most one may be ingested (if the learner missed it)
    send(episodes_, real);
    episodes_.WaitForAcks(seconds(5));

    // weights at a huge version
    if (auto w = Newest(weights_in_, milliseconds(500))) latest_weights_ = *w;
    rl::WeightsUpdate base = latest_weights_.value_or(testing::MakePolicyWeights(n));
    base.version = huge;
    rl::WeightsUpdate w = base;
    w.parameters.pop_back();
    send_alone(weights_, w);
    w = base;
    w.parameters[w.parameters.size() / 3] = 1e30f;
    send_alone(weights_, w);
    w = base;
    w.parameters[0] = kNaN;
    send_alone(weights_, w);
    w = base;
    w.architecture = "attention-policy/not-this-run";
    send_alone(weights_, w);

    // graphs: too many entities (every edge set), a sample of another shape
    send_alone(graphs_, testing::MakeCompleteGraph(16, huge));
    rl::GraphUpdate g = testing::MakeInteractionGraph(n);
    g.version = huge;
    send_alone(graphs_, g);

    // learner stats of a stranger
    if (auto s = Newest(stats_in_, milliseconds(200))) latest_stats_ = *s;
    rl::LearnerReport s = latest_stats_.value_or(testing::MakeLearnerStats(n));
    const uint64_t budget = s.budget_env_steps;
    s.budget_env_steps = s.training_env_steps = s.transitions_inserted = std::max<uint64_t>(budget / 2, 1);
    send_alone(stats_, s);  // done, another budget
    s.budget_env_steps = s.training_env_steps = budget;
    s.transitions_inserted = 10;
    send_alone(stats_, s);  // done with fewer transitions than steps
    s.training_env_steps = s.transitions_inserted = huge;
    send_alone(stats_, s);  // beyond any budget

    // evaluations that cannot be
    rl::EvalReport r = testing::MakeEvalResult(n);
    r.summary.avg_distance = r.summary.avg_object_distance = kNaN;
    send(evals_, r);
    r = testing::MakeEvalResult(n);
    r.policy_version = huge;
    r.summary.avg_object_distance = -1.0f;
    send(evals_, r);

    // a status that would drive a terminal
    rl::NodeStatus st = testing::MakeNodeStatus(900 + n % 10);
    st.role = "intruder\x1b[2J";
    st.host = "lab\r\nhost\x07";
    st.report.detail = "\x1b]0;owned\x07\x1b[31m red";
    send(status_, st);
    return written;
  }

  bool had_template() const { return had_template_; }

 private:
  // One valid episode of this run from the episode topic (its reader lives only for this: a
  // reliable keep-all reader that stopped taking would hold back the actors).
  std::optional<rl::Episode> TakeRunEpisode() {
    ReaderOptions options;
    options.episode_limits = rl::EpisodeLimitsFor(config_.env);
    Reader<rl::Episode> reader(participant_, options);
    rl::Episode episode;
    had_template_ = reader.Take(&episode, seconds(20)) == TakeStatus::kSample;
    if (!had_template_) return std::nullopt;
    return episode;
  }

  config::Config config_;
  Participant participant_;
  Writer<rl::Episode> episodes_;
  Writer<rl::WeightsUpdate> weights_;
  Writer<rl::GraphUpdate> graphs_;
  Writer<rl::LearnerReport> stats_;
  Writer<rl::EvalReport> evals_;
  Writer<rl::NodeStatus> status_;
  Reader<rl::WeightsUpdate> weights_in_;
  Reader<rl::LearnerReport> stats_in_;
  rl::Episode template_episode_;
  std::optional<rl::WeightsUpdate> latest_weights_;
  std::optional<rl::LearnerReport> latest_stats_;
  bool had_template_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: bench_soak RUN_CONFIG BURSTS PERIOD_S\n";
    return 2;
  }
  try {
    Shutdown::InstallSignalHandlers();
    const config::Config config = config::LoadConfig(argv[1]);
    const int bursts = std::stoi(argv[2]);
    const double period = std::stod(argv[3]);
    Injector injector(config);
    const auto start = std::chrono::steady_clock::now();
    for (int n = 0; n < bursts && !Shutdown::Process().requested(); ++n) {
      const auto due = start + std::chrono::duration_cast<milliseconds>(std::chrono::duration<double>(period * n));
      while (std::chrono::steady_clock::now() < due && !Shutdown::Process().requested())
        std::this_thread::sleep_for(milliseconds(100));
      if (Shutdown::Process().requested()) break;
      const int written = injector.Burst(static_cast<uint64_t>(n));
      std::cout << "burst " << n << ": " << written << " samples, episode template "
                << (injector.had_template() ? "from the run" : "none (test sample)") << std::endl;
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_soak: " << e.what() << "\n";
    return 6;
  }
  return 0;
}
