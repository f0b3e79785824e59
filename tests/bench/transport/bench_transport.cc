// ./tests/bench.sh transport: samples/s and MB/s from one writer process to one reader process
// on loopback through srics_transport, for a 20-step 5-entity Episode and a 5 MB
// PolicyWeights, and ddsperf (Cyclone's own tool, same XML profile) at the same payload sizes.
// Prints a table, then one JSON line: {"bench":"transport", ..., "ratio": ours/ddsperf} where
// "ratio" is the episode path actors use (the writer DdsActorLink creates, batched within
// transport.episode_batch_ms, each episode checked as the link does, taken as the learner
// does); "unbatched_ratio" a writer that sends a datagram per episode; "weights_ratio" the
// learner's publication (DdsLearnerLink::PublishWeights: a fresh copy of the parameters moved
// into the message) to a reader as the actor's (validated, moved out).
//
//   bench_transport [--repeats N] [--episodes N] [--weights N] [--ddsperf-seconds S] [--keystore DIR]
//                   [--rows 012] [--no-ddsperf]    (rows: 0 actor path, 1 unbatched, 2 weights)
//   bench_transport --reader KIND COUNT DOMAIN RUN_ID [KEYSTORE]    (the child process)
//
// --keystore DIR (deploy/security/make-keystore.sh): our rows with DDS Security, episodes from
// identity actor-0 to learner, weights from learner to actor-0 (ddsperf stays open).

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "common/transport/dds_links.h"
#include "common/transport/transport.h"
#include "common/transport/wire.h"
#include "tests/common/transport/peer_process.h"
#include "tests/common/transport/test_samples.h"

namespace {

using namespace srics::transport;
namespace rl = srics::rl;
using Clock = std::chrono::steady_clock;
using std::chrono::seconds;

constexpr size_t kWeightBytes = 5 * 1024 * 1024;

struct Options {
  int repeats = 5;
  uint64_t episodes = 100000;
  uint64_t weights = 150;
  int ddsperf_seconds = 4;
  std::string keystore;      // DDS Security for our rows (empty: open)
  std::string rows = "012";  // which rows to run (profiling one path): 0 batched, 1 unbatched, 2 weights
  bool ddsperf = true;       // --no-ddsperf: our rows only (profiling)
};

// One measured run: samples over the reader's first-to-last receive interval.
struct Figure {
  double samples_per_s = 0;
  double mb_per_s = 0;
  double delivered = 0;      // samples the reader got (weights: latest wins, some are skipped)
  double written_per_s = 0;  // the writer's own pace
};

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

// Approximate CDR size of an episode (header, scalars, strings, sequences).
size_t EpisodeBytes(const srics::rl::Episode& e) {
  return 96 + 20 /* run id */ + 2 * e.entity_kinds.size() + 4 * (e.states.size() + e.actions.size() + e.goal.size());
}

// ------------------------------------------------------------------- the reader process

template <typename T>
int RunReader(const Participant& participant, uint64_t count, size_t bytes_per_sample) {
  Reader<T> reader(participant, testing::SampleEpisodeReader());
  std::cout << "ready" << std::endl;
  std::vector<T> batch;
  uint64_t received = 0;
  Clock::time_point first, last;
  bool done = false;
  while (!done) {
    batch.clear();
    const size_t n = reader.TakeMany(&batch, 64, seconds(30));
    if (n == 0) return 4;
    if (received == 0) first = Clock::now();
    received += n;
    last = Clock::now();
    // weights are keep-last 1 (latest wins): stop at the last version, count what arrived
    if constexpr (std::is_same_v<T, rl::WeightsUpdate>) {
      done = batch.back().version == count;  // taken as DdsActorLink::PollWeights hands it on
    } else {
      done = received >= count;
    }
  }
  // the first sample's arrival starts the clock, so it does not count
  const double s = std::chrono::duration<double>(last - first).count();
  std::cout << "result " << (received - 1) / s << " " << (received - 1) * bytes_per_sample / s / 1e6 << " " << received
            << std::endl;
  return 0;
}

// The identity of the writing (`writer`) or reading side of `kind` with a keystore.
srics::config::SecurityConfig SecurityOf(const std::string& keystore, const std::string& kind, bool writer) {
  if (keystore.empty()) return {};
  return {keystore, (kind == "episode") == writer ? "actor-0" : "learner"};
}

int ReaderMain(const std::string& kind, uint64_t count, int domain, const std::string& run,
               const std::string& keystore) {
  srics::config::TransportConfig config;
  config.domain_id = domain;
  config.run_id = run;
  config.security = SecurityOf(keystore, kind, false);
  config.episode_history_depth = 1024;
  Participant participant(config);
  if (kind == "episode")
    return RunReader<srics::rl::Episode>(participant, count, EpisodeBytes(testing::MakeEpisode(0)));
  return RunReader<rl::WeightsUpdate>(participant, count, kWeightBytes);
}

// ------------------------------------------------------------------- the writer process

std::string Self() {
  char path[4096];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  return n > 0 ? std::string(path, n) : "bench_transport";
}

// actor_path: the writer an actor's DdsActorLink creates (ActorEpisodeWriterOptions: batched,
// each episode sent within transport.episode_batch_ms), checking each episode as the link does.
template <typename T>
std::optional<Figure> RunOnce(const std::string& kind, T sample, uint64_t count, int domain, bool actor_path,
                              const std::string& keystore) {
  srics::config::TransportConfig config;
  config.domain_id = domain;
  config.run_id = "bench-" + std::to_string(getpid());
  config.security = SecurityOf(keystore, kind, true);
  Participant participant(config);
  WriterOptions options;
  if (actor_path) {
    options = ActorEpisodeWriterOptions(config);
    options.validate = true;  // the link's own check (rl::ValidateEpisode), done by the writer here
  }
  Writer<T> writer(participant, options);
  std::vector<std::string> reader_args = {"--reader", kind, std::to_string(count), std::to_string(domain),
                                          config.run_id};
  if (!keystore.empty()) reader_args.push_back(keystore);
  testing::PeerProcess reader(Self(), reader_args);
  auto fail = [&](const std::string& why) -> std::optional<Figure> {
    const std::optional<int> code = reader.Wait(seconds(10));
    std::cerr << kind << " run: " << why << " (reader exit code " << (code ? std::to_string(*code) : "none") << ")\n";
    return {};
  };
  if (reader.ReadLine(seconds(20)) != "ready") return fail("the reader was not ready in 20 s");
  if (!writer.WaitForReaders(1, seconds(20))) return fail("the reader did not match in 20 s");
  const auto start = Clock::now();
  for (uint64_t i = 0; i < count; ++i) {
    if constexpr (std::is_same_v<T, rl::WeightsUpdate>) {
      // DdsLearnerLink::PublishWeights: the learner's fresh copy of its parameters (as
      // Learner::TakePolicyWeights makes) written as it is, envelope and checksum stamped by
      // the writer on the C sample
      rl::WeightsUpdate update = sample;
      update.version = i + 1;
      if (writer.Write(update) != WriteResult::kSent) return fail("a write was not sent");
    } else {
      if (writer.Write(sample) != WriteResult::kSent) return fail("a write was not sent");
    }
  }
  const double write_s = std::chrono::duration<double>(Clock::now() - start).count();
  (void)writer.WaitForAcks(seconds(60));
  const auto line = reader.ReadLine(seconds(60));
  if (!line || line->rfind("result ", 0) != 0) return fail("the reader said '" + line.value_or("") + "'");
  std::istringstream in(line->substr(7));
  Figure f;
  in >> f.samples_per_s >> f.mb_per_s >> f.delivered;
  f.written_per_s = count / write_s;
  reader.Wait(seconds(10));
  return f;
}

// ----------------------------------------------------------------------------- ddsperf

// Runs ddsperf sub and pub (reliable, keep-all) with `bytes` payload; the median of the
// subscriber's full one-second rates. `unbatched`: the publisher with write batching kept off
// (ddsperf always switches it on; a preloaded no-op switch keeps it off).
std::optional<Figure> RunDdsperf(size_t bytes, int domain, int duration_s, const std::string& xml,
                                 bool unbatched = false) {
  setenv("CYCLONEDDS_URI", ("file://" + xml).c_str(), 1);
  const std::string d = std::to_string(domain);
  testing::PeerProcess sub("/usr/bin/ddsperf", {"-i", d, "-D", std::to_string(duration_s + 1), "-k", "all", "sub"});
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  if (unbatched) setenv("LD_PRELOAD", SRICS_DDSPERF_UNBATCHED, 1);
  testing::PeerProcess pub("/usr/bin/ddsperf", {"-i", d, "-D", std::to_string(duration_s), "-k", "all", "pub", "size",
                                                std::to_string(bytes)});
  unsetenv("LD_PRELOAD");
  // "... size S total N lost L delta D lost L rate R kS/s B Mb/s (...)"
  const std::regex rate(R"(size \d+ total \d+ lost \d+ delta \d+ lost \d+ rate ([0-9.]+) kS/s ([0-9.]+) Mb/s)");
  std::vector<double> rates, mbits;
  while (auto line = sub.ReadLine(seconds(duration_s + 10))) {
    std::smatch m;
    if (std::regex_search(*line, m, rate)) {
      rates.push_back(std::stod(m[1]) * 1e3);
      mbits.push_back(std::stod(m[2]));
    }
  }
  pub.Wait(seconds(10));
  sub.Wait(seconds(10));
  unsetenv("CYCLONEDDS_URI");
  // drop the first and last seconds (start-up, partial second)
  if (rates.size() >= 3) {
    rates = std::vector<double>(rates.begin() + 1, rates.end() - 1);
    mbits = std::vector<double>(mbits.begin() + 1, mbits.end() - 1);
  }
  if (rates.empty()) return {};
  return Figure{Median(rates), Median(mbits) / 8};
}

// ------------------------------------------------------------------------------- main

struct Row {
  std::string name;
  size_t bytes;
  std::vector<double> ours, ours_mb, ddsperf, ddsperf_mb;
  // ours / ddsperf of one repeat, the two measured back to back (on a loaded machine the
  // pairs see similar loads; the medians of the rates may come from different moments)
  std::vector<double> paired;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if ((args.size() == 5 || args.size() == 6) && args[0] == "--reader") {
    try {
      return ReaderMain(args[1], std::stoull(args[2]), std::stoi(args[3]), args[4], args.size() == 6 ? args[5] : "");
    } catch (const std::exception& e) {
      std::cerr << "reader: " << e.what() << "\n";
      return 6;
    }
  }
  Options o;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--no-ddsperf") {
      o.ddsperf = false;
      continue;
    }
    if (i + 1 >= args.size()) {
      std::cerr << args[i] << " needs a value\n";
      return 2;
    }
    const std::string& value = args[++i];
    if (args[i - 1] == "--repeats")
      o.repeats = std::stoi(value);
    else if (args[i - 1] == "--episodes")
      o.episodes = std::stoull(value);
    else if (args[i - 1] == "--weights")
      o.weights = std::stoull(value);
    else if (args[i - 1] == "--ddsperf-seconds")
      o.ddsperf_seconds = std::stoi(value);
    else if (args[i - 1] == "--keystore")
      o.keystore = value;
    else if (args[i - 1] == "--rows")
      o.rows = value;
    else {
      std::cerr << "unknown option " << args[i - 1] << "\n";
      return 2;
    }
  }
  const std::string xml = std::string(SRICS_SOURCE_DIR) + "/deploy/cyclonedds/loopback.xml";
  // actor 0's episode: with --keystore the writer is identity actor-0, and a reader refuses an
  // episode that names another actor (transport::SenderIdentity)
  const srics::rl::Episode episode = [] {
    srics::rl::Episode e = testing::MakeEpisode(0);
    e.actor_id = 0;
    return e;
  }();
  const rl::WeightsUpdate weights = testing::MakePolicyWeights(1, kWeightBytes / sizeof(float));
  // the actor path (row 0) is what actors use; ddsperf batches its writes too
  constexpr int kRows = 3;
  const int batch_ms = srics::config::TransportConfig{}.episode_batch_ms;
  Row rows[kRows] = {
      {"episode, actor path (batch " + std::to_string(batch_ms) + " ms)", EpisodeBytes(episode), {}, {}, {}, {}, {}},
      {"episode, unbatched writer", EpisodeBytes(episode), {}, {}, {}, {}, {}},
      {"policy weights 5 MiB", kWeightBytes + 360, {}, {}, {}, {}, {}}};
  std::vector<double> ddsperf_unbatched;
  int domain = 20 + static_cast<int>(getpid() % 150);
  for (int r = 0; r < o.repeats; ++r) {
    double ours_now[kRows] = {};  // this repeat's rates (0: not run or failed)
    double ddsperf_now0 = 0;      // and ddsperf's at the episode size
    for (int k = 0; k < kRows; ++k) {
      if (o.rows.find(static_cast<char>('0' + k)) == std::string::npos) continue;
      std::optional<Figure> f = k < 2 ? RunOnce("episode", episode, o.episodes, domain++, k == 0, o.keystore)
                                      : RunOnce("weights", weights, o.weights, domain++, false, o.keystore);
      if (f)
        std::fprintf(stderr, "%s: writer %.0f/s, reader %.0f/s, %.0f delivered\n", rows[k].name.c_str(),
                     f->written_per_s, f->samples_per_s, f->delivered);
      if (f) {
        ours_now[k] = f->samples_per_s;
        rows[k].ours.push_back(f->samples_per_s);
        rows[k].ours_mb.push_back(f->mb_per_s);
      } else {
        std::cerr << "run " << r << " of " << rows[k].name << " failed\n";
      }
      if (k == 1) {  // same payload size as row 0: one ddsperf run serves both
        rows[1].ddsperf = rows[0].ddsperf;
        rows[1].ddsperf_mb = rows[0].ddsperf_mb;
        if (ours_now[1] > 0 && ddsperf_now0 > 0) rows[1].paired.push_back(ours_now[1] / ddsperf_now0);
        // and the floor of a datagram per sample: ddsperf with batching kept off
        if (!o.ddsperf) continue;
        if (auto p = RunDdsperf(rows[1].bytes, domain++, o.ddsperf_seconds, xml, /*unbatched=*/true))
          ddsperf_unbatched.push_back(p->samples_per_s);
        else
          std::cerr << "unbatched ddsperf run " << r << " failed\n";
        continue;
      }
      if (!o.ddsperf) continue;
      std::optional<Figure> p = RunDdsperf(rows[k].bytes, domain++, o.ddsperf_seconds, xml);
      if (p) {
        rows[k].ddsperf.push_back(p->samples_per_s);
        rows[k].ddsperf_mb.push_back(p->mb_per_s);
        if (k == 0) ddsperf_now0 = p->samples_per_s;
        if (ours_now[k] > 0 && p->samples_per_s > 0) rows[k].paired.push_back(ours_now[k] / p->samples_per_s);
      } else {
        std::cerr << "ddsperf run " << r << " at " << rows[k].bytes << " B failed\n";
      }
    }
  }
  std::printf(
      "transport benchmark: one writer process -> one reader process, loopback, reliable "
      "keep-all, medians of %d runs%s\n",
      o.repeats, o.keystore.empty() ? "" : "; ours with DDS Security (encrypted payloads, signed submessages)");
  std::printf("%-36s %10s %14s %10s %14s %10s %7s %7s\n", "payload", "bytes", "ours samples/s", "ours MB/s",
              "ddsperf smp/s", "ddsp MB/s", "ratio", "paired");
  double ratio[kRows], paired[kRows];
  for (int k = 0; k < kRows; ++k) {
    const double ours = Median(rows[k].ours), ref = Median(rows[k].ddsperf);
    ratio[k] = ref > 0 ? ours / ref : 0;
    paired[k] = Median(rows[k].paired);
    std::printf("%-36s %10zu %14.0f %10.1f %14.0f %10.1f %7.2f %7.2f\n", rows[k].name.c_str(), rows[k].bytes, ours,
                Median(rows[k].ours_mb), ref, Median(rows[k].ddsperf_mb), ratio[k], paired[k]);
  }
  const double floor = Median(ddsperf_unbatched);
  const double unbatched_vs_floor = floor > 0 ? Median(rows[1].ours) / floor : 0;
  std::printf("%-36s %10zu %14s %10s %14.0f %10s %7.2f\n", "ddsperf with batching off (floor)", rows[1].bytes, "", "",
              floor, "", unbatched_vs_floor);
  std::printf(
      "ratio: median of our rates over the median of ddsperf's (JSON \"ratio\", \"unbatched_ratio\",\n"
      "\"weights_ratio\"); paired: the median of each repeat's ratio, ours and ddsperf measured back\n"
      "to back (JSON \"*_paired\"), steadier on a loaded machine.\n");
  std::printf(
      "The actor path is the writer actors use (\"ratio\"): batched, each episode sent within\n"
      "transport.episode_batch_ms; ddsperf batches too. The unbatched writer sends a datagram per\n"
      "episode; its like-for-like reference is ddsperf with batching off (last row: our unbatched\n"
      "rate over it). Weights are keep-last 1 (latest wins): their rate counts the distinct samples\n"
      "the reader got while the writer published as fast as it could; ddsperf's is keep-all.\n");
  std::printf(
      "{\"bench\":\"transport\",\"episode_bytes\":%zu,\"episodes_per_s\":%.0f,"
      "\"episode_mb_per_s\":%.1f,\"episodes_per_s_unbatched\":%.0f,"
      "\"ddsperf_episode_size_samples_per_s\":%.0f,\"ddsperf_episode_size_mb_per_s\":%.1f,"
      "\"unbatched_ratio\":%.3f,\"ddsperf_unbatched_samples_per_s\":%.0f,"
      "\"unbatched_vs_ddsperf_unbatched\":%.3f,"
      "\"weights_bytes\":%zu,\"weights_per_s\":%.1f,\"weights_mb_per_s\":%.1f,"
      "\"ddsperf_weights_size_samples_per_s\":%.1f,\"weights_ratio\":%.3f,"
      "\"ratio_paired\":%.3f,\"unbatched_ratio_paired\":%.3f,\"weights_ratio_paired\":%.3f,"
      "\"episode_batch_ms\":%d,\"repeats\":%d,\"secured\":%s,\"ratio\":%.3f}\n",
      rows[0].bytes, Median(rows[0].ours), Median(rows[0].ours_mb), Median(rows[1].ours), Median(rows[0].ddsperf),
      Median(rows[0].ddsperf_mb), ratio[1], floor, unbatched_vs_floor, rows[2].bytes, Median(rows[2].ours),
      Median(rows[2].ours_mb), Median(rows[2].ddsperf), ratio[2], paired[0], paired[1], paired[2], batch_ms, o.repeats,
      o.keystore.empty() ? "false" : "true", ratio[0]);
  return 0;
}
