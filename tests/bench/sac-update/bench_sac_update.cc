// ./tests/bench.sh sac-update: milliseconds per full SAC update (batch sampling and goal
// relabeling, twin critics, policy, temperature, target update) with the paper's networks on
// Rearrange 3 (4 entities), at batch 2048 and 256, with 1 and 2 learner threads
// (learner.threads); the agent's update alone on a fixed batch (what the PyTorch peer of
// run.sh times), also with Eigen's GEMM instead of oneDNN's (common/nn/gemm.h); in the same run
// the GEMM floor (the same matrix products, bare, through the same GEMM) and the single-thread
// sgemm rate of Eigen and of oneDNN at 2048 x 2048 x 2048.
//
// bench_sac_update [--dump DIR]: DIR receives what the PyTorch peer needs to run the same
// update: spec.json (sizes and SAC settings from the config) and batch<B>.bin (the batch).
// bench_sac_update --only BATCH: the agent's update on a fixed batch of BATCH, one thread, fp32
// and (where the CPU has it) bf16, as one JSON line: short enough to pair two builds in turn
// (farm-bench) when a change to the update is timed against its parent.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "actor/env/rearrange_env.h"
#include "actor/explore_episode.h"
#include "common/config/config.h"
#include "common/nn/gemm.h"
#include "common/process/memory.h"
#include "learner/learner.h"
#include "tests/bench/bench_util.h"

namespace {

using namespace srics;

const char* kConfig = "/deploy/configs/rearrange-3.yaml";

// Median wall ms of `repeats` calls after a warm-up, and over those calls the process's CPU
// time per call and CPU time / wall time: the cores the process actually got (on a machine
// shared with other work, a second thread helps only as far as this exceeds 1).
struct Timing {
  double ms = 0, cpu_ms = 0, cores = 0;
};

double ProcessCpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

template <typename F>
Timing Time(int repeats, F&& f) {
  const double cpu0 = ProcessCpuSeconds();
  const auto wall0 = std::chrono::steady_clock::now();
  Timing t;
  t.ms = bench::MedianMs(repeats, f);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double cpu = ProcessCpuSeconds() - cpu0;
  t.cpu_ms = 1e3 * cpu / (repeats + 1);
  t.cores = cpu / wall;
  return t;
}

struct Result {
  int batch = 0, threads = 0;
  double update_ms = 0;      // Learner::Update: sampling, relabeling and the agent's update
  double agent_ms = 0;       // SacAgent::Update on a fixed batch
  Timing agent;              // the same with CPU time and cores obtained
  Timing agent_eigen;        // one thread only: the agent's update with Eigen's GEMM
  Timing agent_bf16;         // one thread only, where the CPU has it: with learner.precision bf16
  double floor_ms = 0;       // one thread only: the GEMM floor
  double floor_bf16_ms = 0;  // the same products in bf16, where the CPU has them (0: not measured)
  double gflop = 0;          // GEMM work of one update (from the layer shapes, forward + backward)
  size_t gemms = 0;
};

config::Config LoadFor(int batch, int threads) {
  return config::LoadConfig(std::string(SRICS_SOURCE_DIR) + kConfig,
                            {"agent.sac.batch_size=" + std::to_string(batch), "learner.warmup_steps=0",
                             "learner.threads=" + std::to_string(threads)});
}

// batch<B>.bin: int32 B, N, D, G, A; then float32 entities (B*N*D), next_entities, mask (B*N),
// goal (B*G), action (B*A), reward (B), bootstrap (B: 1 - terminal)
void DumpBatch(const std::string& path, const learner::TrainingBatch& b) {
  std::ofstream f(path, std::ios::binary);
  const int32_t head[5] = {b.size, b.max_entities, b.entity_dim, b.goal_dim, b.action_dim};
  f.write(reinterpret_cast<const char*>(head), sizeof head);
  auto put = [&](const std::vector<float>& v) { f.write(reinterpret_cast<const char*>(v.data()), v.size() * 4); };
  put(b.entities);
  put(b.next_entities);
  put(b.mask);
  put(b.goal);
  put(b.action);
  put(b.reward);
  std::vector<float> boot(b.size, 1.0f);
  for (size_t i = 0; i < b.terminal.size(); ++i) boot[i] = 1.0f - b.terminal[i];
  put(boot);
  if (!f) throw std::runtime_error("cannot write " + path);
}

void DumpSpec(const std::string& path, const config::Config& c, const learner::Learner& l) {
  const auto& n = c.agent.network;
  const auto& s = c.agent.sac;
  auto list = [](const std::vector<int>& v) {
    std::string out = "[";
    for (size_t i = 0; i < v.size(); ++i) out += (i ? "," : "") + std::to_string(v[i]);
    return out + "]";
  };
  std::ofstream f(path);
  f << "{\"entity_dim\":" << l.shape().entity_dim << ",\"goal_dim\":" << l.shape().goal_dim
    << ",\"action_dim\":" << l.shape().action_dim << ",\"embed_dim\":" << n.embed_dim << ",\"heads\":" << n.heads
    << ",\"policy_hidden\":" << list(n.policy_hidden) << ",\"q_hidden\":" << list(n.q_hidden)
    << ",\"log_std_min\":" << n.log_std_min << ",\"log_std_max\":" << n.log_std_max << ",\"discount\":" << s.discount
    << ",\"tau\":" << s.tau << ",\"policy_lr\":" << s.policy_lr << ",\"q_lr\":" << s.q_lr
    << ",\"alpha_lr\":" << s.alpha_lr << ",\"auto_entropy\":" << (s.auto_entropy ? "true" : "false")
    << ",\"initial_alpha\":" << s.initial_alpha << ",\"target_entropy\":" << s.target_entropy
    << ",\"reward_scale\":" << s.reward_scale << ",\"grad_clip_norm\":" << s.grad_clip_norm << "}\n";
  if (!f) throw std::runtime_error("cannot write " + path);
}

// agent_only: the agent's update alone, fp32 and bf16 (no Learner::Update, Eigen or floor)
Result Measure(int batch, int threads, const std::vector<rl::Episode>& episodes, int repeats,
               const std::string& dump_dir, bool agent_only = false) {
  const config::Config c = LoadFor(batch, threads);
  learner::Learner learner(learner::LearnerOptionsFor(c, rl::RunShapeFor(c)));
  learner.SetGraph(rl::ComputeSubgoalStructure(rl::InteractionGraph::Star(4)));
  for (const auto& e : episodes) learner.Ingest(e);
  Result r;
  r.batch = batch;
  r.threads = threads;
  std::vector<nn::GemmShape> shapes;
  if (threads == 1) learner.agent().set_gemm_log(&shapes);
  learner.Update();
  learner.agent().set_gemm_log(nullptr);
  if (!agent_only) r.update_ms = bench::MedianMs(repeats, [&] { learner.Update(); });
  const learner::TrainingBatch fixed = learner.last_batch();
  r.agent = Time(repeats, [&] { learner.agent().Update(fixed); });
  r.agent_ms = r.agent.ms;
  if (threads == 1) {
    const nn::GemmBackend active = nn::ActiveGemmBackend();
    if (!agent_only) {
      nn::SetGemmBackend(nn::GemmBackend::kEigen);
      r.agent_eigen = Time(repeats, [&] { learner.agent().Update(fixed); });
      nn::SetGemmBackend(active);
    }
    if (learner.agent().SetProductPrecision(nn::GemmPrecision::kBf16) == nn::GemmPrecision::kBf16) {
      learner.agent().Update(fixed);  // builds the bf16 products' primitives, outside the timing
      r.agent_bf16 = Time(repeats, [&] { learner.agent().Update(fixed); });
      learner.agent().SetProductPrecision(nn::GemmPrecision::kFp32);
    }
    if (agent_only) return r;
    bench::GemmFloor floor(shapes);
    r.floor_ms = bench::MedianMs(repeats, [&] { floor.Run(); });
    if (r.agent_bf16.cpu_ms > 0) {  // the update's bf16 products bare: what no overhead cut goes below
      const nn::ScopedGemmPrecision precision(nn::GemmPrecision::kBf16);
      floor.Run();  // builds the bf16 primitives outside the timing
      r.floor_bf16_ms = bench::MedianMs(repeats, [&] { floor.Run(); });
    }
    r.gflop = floor.Flops() * 1e-9;
    r.gemms = shapes.size();
    if (!dump_dir.empty()) {
      DumpBatch(dump_dir + "/batch" + std::to_string(batch) + ".bin", fixed);
      DumpSpec(dump_dir + "/spec.json", c, learner);
    }
  }
  return r;
}

// A backend's single-thread float GEMM rate, 2048 x 2048 x 2048, GFLOP/s: best of 5 by wall
// time and by process CPU time (the latter holds on a machine shared with other work).
struct Rate {
  double wall = 0, cpu = 0;
};
Rate SgemmGflops(nn::GemmBackend backend) {
  const nn::GemmBackend active = nn::ActiveGemmBackend();
  nn::SetGemmBackend(backend);
  const int n = 2048;
  const nn::Tensor a = nn::Tensor::Random(n, n), b = nn::Tensor::Random(n, n);
  nn::Tensor c(n, n);
  double best_wall = 1e30, best_cpu = 1e30;
  for (int i = 0; i < 5; ++i) {
    const double cpu0 = ProcessCpuSeconds();
    const auto start = std::chrono::steady_clock::now();
    nn::Gemm<float>(false, false, a, b, 0.0f, c);
    best_wall = std::min(best_wall, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    best_cpu = std::min(best_cpu, ProcessCpuSeconds() - cpu0);
  }
  nn::SetGemmBackend(active);
  const double flop = 2.0 * n * n * n;
  return {flop / best_wall * 1e-9, flop / best_cpu * 1e-9};
}

}  // namespace

int main(int argc, char** argv) {
  // the heap as the learner's processes set it up (before 2026-12-06 the bench left glibc's
  // defaults and missed what big buffers cost there: page faults and munmaps at batch 2048)
  srics::process::SetUpHeap();
  std::string dump_dir;
  int only_batch = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--dump" && i + 1 < argc) {
      dump_dir = argv[++i];
    } else if (arg == "--only" && i + 1 < argc && std::atoi(argv[i + 1]) > 0) {
      only_batch = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: %s [--dump DIR | --only BATCH]\n", argv[0]);
      return 2;
    }
  }
  config::Config c = config::LoadConfig(std::string(SRICS_SOURCE_DIR) + kConfig);
  auto env = env::MakeRearrangeEnv(c.env);
  nn::Rng rng(1);
  std::vector<rl::Episode> episodes;
  for (int i = 0; i < 200; ++i)
    if (auto e = actor::RunExploreEpisode(*env, 50, 1000 + i, rng)) episodes.push_back(std::move(*e));

  if (only_batch > 0) {
    const Result r = Measure(only_batch, 1, episodes, only_batch >= 1024 ? 11 : 41, "", /*agent_only=*/true);
    std::printf(
        "{\"bench\":\"sac-update --only\",\"batch\":%d,\"agent_ms\":%.3f,\"agent_cpu_ms\":%.3f,"
        "\"agent_cpu_ms_bf16\":%.3f}\n",
        r.batch, r.agent_ms, r.agent.cpu_ms, r.agent_bf16.cpu_ms);
    return 0;
  }
  std::printf(
      "SAC update, paper networks (attention 80 = 5 x 16, policy [128,128], Q [128,128,128]),\n"
      "Rearrange 3 (4 entities), median of repeats. update = Learner::Update (sampling, relabeling,\n"
      "SAC step); agent = SacAgent::Update on a fixed batch; floor = its matrix products as bare Eigen\n\n");
  std::printf("%-6s %8s %11s %10s %12s %7s %14s %8s %7s\n", "batch", "threads", "update ms", "agent ms", "agent cpu ms",
              "cores", "GEMM floor ms", "ratio", "gemms");
  const Result big1 = Measure(2048, 1, episodes, 11, dump_dir);
  const Result big2 = Measure(2048, 2, episodes, 11, "");
  const Result small1 = Measure(256, 1, episodes, 41, dump_dir);
  const Result small2 = Measure(256, 2, episodes, 41, "");
  for (const Result& r : {big1, big2, small1, small2}) {
    if (r.threads == 1)
      std::printf("%-6d %8d %11.2f %10.2f %12.2f %7.2f %14.2f %8.2f %7zu\n", r.batch, r.threads, r.update_ms,
                  r.agent_ms, r.agent.cpu_ms, r.agent.cores, r.floor_ms, r.update_ms / r.floor_ms, r.gemms);
    else
      std::printf("%-6d %8d %11.2f %10.2f %12.2f %7.2f %14s %8s %7s\n", r.batch, r.threads, r.update_ms, r.agent_ms,
                  r.agent.cpu_ms, r.agent.cores, "", "", "");
  }
  const Rate eigen = SgemmGflops(nn::GemmBackend::kEigen);
  const double eigen_gflops = eigen.wall;
  const bool have_onednn = nn::GemmBackendAvailable(nn::GemmBackend::kOneDnn);
  const Rate onednn = have_onednn ? SgemmGflops(nn::GemmBackend::kOneDnn) : Rate{};
  std::printf(
      "\nGEMM in use: %s; the agent's update with Eigen's GEMM instead, CPU ms: %.2f at 2048, %.2f at 256\n"
      "(this GEMM over Eigen's, by CPU time: %.2fx at 2048, %.2fx at 256)\n",
      nn::GemmBackendDescription().c_str(), big1.agent_eigen.cpu_ms, small1.agent_eigen.cpu_ms,
      big1.agent_eigen.cpu_ms / big1.agent.cpu_ms, small1.agent_eigen.cpu_ms / small1.agent.cpu_ms);
  const bool bf16 = nn::Bf16ProductsAvailable();
  if (bf16)
    std::printf(
        "bf16 products (learner.precision: bf16), the agent's update, CPU ms: %.2f at 2048 (%.2fx fp32's), %.2f at 256 "
        "(%.2fx);\nits products bare in bf16 (the floor no cut of the update's other work goes below): %.2f ms at "
        "2048, %.2f at 256\n",
        big1.agent_bf16.cpu_ms, big1.agent_bf16.cpu_ms / big1.agent.cpu_ms, small1.agent_bf16.cpu_ms,
        small1.agent_bf16.cpu_ms / small1.agent.cpu_ms, big1.floor_bf16_ms, small1.floor_bf16_ms);
  else
    std::printf("bf16 products: not on this CPU (no AVX-512 BF16 or AMX, or oneDNN's cap)\n");
  std::printf("\nupdates per second, 1 thread: %.1f at batch 2048, %.0f at 256; 2 threads: %.1f, %.0f\n",
              1000.0 / big1.update_ms, 1000.0 / small1.update_ms, 1000.0 / big2.update_ms, 1000.0 / small2.update_ms);
  std::printf("2 threads vs 1 (updates/s): %.2fx at batch 2048, %.2fx at 256 (agent alone: %.2fx, %.2fx)\n",
              big1.update_ms / big2.update_ms, small1.update_ms / small2.update_ms, big1.agent_ms / big2.agent_ms,
              small1.agent_ms / small2.agent_ms);
  std::printf(
      "cores obtained by the 2-thread agent update (process CPU / wall): %.2f at 2048, %.2f at 256;\n"
      "its CPU time over the 1-thread update's (the cost of sharding): %.2f at 2048, %.2f at 256\n",
      big2.agent.cores, small2.agent.cores, big2.agent.cpu_ms / big1.agent.cpu_ms,
      small2.agent.cpu_ms / small1.agent.cpu_ms);
  std::printf(
      "GEMM work per update (layer shapes, forward + backward): %.2f GFLOP at 2048, %.3f at 256;\n"
      "sgemm 2048^3 one thread: Eigen %.1f, oneDNN %.1f GFLOP/s; the agent's update at 2048, 1 thread: %.1f GFLOP/s\n",
      big1.gflop, small1.gflop, eigen_gflops, onednn.wall, big1.gflop / (big1.agent_ms * 1e-3));
  std::printf(
      "{\"bench\":\"sac-update\",\"ms_batch2048\":%.3f,\"ms_batch256\":%.3f,\"floor_ms_batch2048\":%.3f,"
      "\"floor_ms_batch256\":%.3f,\"agent_ms_batch2048\":%.3f,\"agent_ms_batch256\":%.3f,"
      "\"ms_batch2048_2threads\":%.3f,\"ms_batch256_2threads\":%.3f,\"agent_ms_batch2048_2threads\":%.3f,"
      "\"agent_ms_batch256_2threads\":%.3f,\"speedup_2_threads_2048\":%.3f,\"speedup_2_threads_256\":%.3f,"
      "\"agent_cpu_ms_batch2048\":%.3f,\"agent_cpu_ms_batch256\":%.3f,\"cores_1thread_2048\":%.2f,"
      "\"cores_2threads_2048\":%.2f,\"cores_2threads_256\":%.2f,\"cpu_ratio_2threads_2048\":%.3f,"
      "\"cpu_ratio_2threads_256\":%.3f,\"gflop_update_2048\":%.4f,\"gflop_update_256\":%.5f,\"eigen_sgemm_gflops\":%."
      "2f,\"eigen_sgemm_gflops_cpu\":%.2f,"
      "\"onednn_sgemm_gflops\":%.2f,\"onednn_sgemm_gflops_cpu\":%.2f,\"gemm_backend\":\"%s\","
      "\"agent_cpu_ms_batch2048_eigen\":%.3f,\"agent_cpu_ms_batch256_eigen\":%.3f,"
      "\"speedup_vs_eigen_cpu_2048\":%.3f,\"speedup_vs_eigen_cpu_256\":%.3f,\"bf16\":%s,"
      "\"agent_cpu_ms_batch2048_bf16\":%.3f,\"agent_cpu_ms_batch256_bf16\":%.3f,\"floor_ms_batch2048_bf16\":%.3f,"
      "\"floor_ms_batch256_bf16\":%.3f,\"ratio\":%.3f}\n",
      big1.update_ms, small1.update_ms, big1.floor_ms, small1.floor_ms, big1.agent_ms, small1.agent_ms, big2.update_ms,
      small2.update_ms, big2.agent_ms, small2.agent_ms, big1.update_ms / big2.update_ms,
      small1.update_ms / small2.update_ms, big1.agent.cpu_ms, small1.agent.cpu_ms, big1.agent.cores, big2.agent.cores,
      small2.agent.cores, big2.agent.cpu_ms / big1.agent.cpu_ms, small2.agent.cpu_ms / small1.agent.cpu_ms, big1.gflop,
      small1.gflop, eigen_gflops, eigen.cpu, onednn.wall, onednn.cpu, nn::GemmBackendDescription().c_str(),
      big1.agent_eigen.cpu_ms, small1.agent_eigen.cpu_ms, big1.agent_eigen.cpu_ms / big1.agent.cpu_ms,
      small1.agent_eigen.cpu_ms / small1.agent.cpu_ms, bf16 ? "true" : "false", big1.agent_bf16.cpu_ms,
      small1.agent_bf16.cpu_ms, big1.floor_bf16_ms, small1.floor_bf16_ms, big1.update_ms / big1.floor_ms);
  return 0;
}
