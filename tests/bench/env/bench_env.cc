// ./tests/bench.sh env: environment steps per second on one core for each preset, against a
// bare loop of mj_step on the same compiled model doing the same physics (the env run's mocap
// targets replayed, frame_skip physics steps per env step). Medians over repeats; env and
// bare runs alternate so that load from other processes hits both alike.
//
// Prints a table, then as the very last line one JSON object:
//   {"bench":"env", "presets":{...}, "ratio": <min over presets of env rate / bare rate>}

#include <mujoco/mujoco.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

#include "actor/env/mujoco_util.h"
#include "actor/env/rearrange_env.h"
#include "common/config/config.h"

namespace {

using Clock = std::chrono::steady_clock;
using namespace srics;

constexpr int kEpisodeSteps = 50;

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Result {
  std::string preset;
  double env_rate = 0;   // env steps per second
  double bare_rate = 0;  // env-step equivalents (frame_skip mj_steps) per second
  int frame_skip = 0;
};

Result Measure(const std::string& preset, int episodes, int repeats) {
  const config::EnvConfig c =
      config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/env/" + preset + ".yaml").env;
  env::RearrangeEnv environment(c);
  const mjModel* m = environment.model();
  env::DataPtr bare = env::MakeData(m);
  const int frame_skip = c.physics.frame_skip;

  // one recorded run: initial states and the mocap target of every step
  std::vector<env::DataPtr> starts;
  std::vector<std::array<double, 3>> mocap;
  std::vector<std::vector<double>> actions;
  env::Rng rng(42);
  for (int e = 0; e < episodes; ++e) {
    std::vector<double> a(2 * kEpisodeSteps);
    for (double& x : a) x = env::Uniform(rng, -1, 1);
    actions.push_back(std::move(a));
  }

  std::vector<double> env_rates, bare_rates;
  std::vector<double> states;
  for (int r = 0; r < repeats; ++r) {
    // the environment: Reset + Step with random actions (as the exploring actors run it)
    const bool record = r == 0;
    auto t0 = Clock::now();
    for (int e = 0; e < episodes; ++e) {
      environment.Reset(static_cast<uint64_t>(e));
      if (record) {
        starts.push_back(env::MakeData(m));
        mj_copyData(starts.back().get(), m, environment.data());
      }
      for (int t = 0; t < kEpisodeSteps; ++t) {
        if (environment.Step(std::span<const double>(&actions[e][2 * t], 2)) != env::StepStatus::kOk) {
          std::fprintf(stderr, "unstable step in %s\n", preset.c_str());
          std::exit(1);
        }
        environment.GetStates(&states);
        if (record) {
          const double* p = environment.data()->mocap_pos;
          mocap.push_back({p[0], p[1], p[2]});
        }
      }
    }
    const double env_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    env_rates.push_back(episodes * kEpisodeSteps / env_seconds);

    // the bare loop: same model, same starts, same mocap targets, only mj_step
    double bare_seconds = 0;
    size_t k = 0;
    for (int e = 0; e < episodes; ++e) {
      mj_copyData(bare.get(), m, starts[e].get());  // not timed: stands in for Reset
      auto b0 = Clock::now();
      for (int t = 0; t < kEpisodeSteps; ++t, ++k) {
        bare->mocap_pos[0] = mocap[k][0];
        bare->mocap_pos[1] = mocap[k][1];
        bare->mocap_pos[2] = mocap[k][2];
        for (int s = 0; s < frame_skip; ++s) mj_step(m, bare.get());
      }
      bare_seconds += std::chrono::duration<double>(Clock::now() - b0).count();
    }
    bare_rates.push_back(episodes * kEpisodeSteps / bare_seconds);
  }
  return {preset, Median(env_rates), Median(bare_rates), frame_skip};
}

}  // namespace

int main(int argc, char** argv) {
  const int episodes = argc > 1 ? std::atoi(argv[1]) : 6;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  const std::vector<std::string> presets = {
      "rearrange-1",  "rearrange-2",         "rearrange-3",          "rearrange-4",
      "relational-4", "relational-4-spring", "rearrange-4-velocity", "rearrange-4-combinations",
      "different-6"};
  std::printf(
      "env steps/s on one core (%d episodes x %d steps, median of %d repeats;\n"
      "bare = mj_step x frame_skip on the same model and mocap targets)\n\n",
      episodes, kEpisodeSteps, repeats);
  std::printf("%-26s %12s %12s %8s %14s\n", "preset", "env/s", "bare/s", "ratio", "mj_step/s");
  std::vector<Result> results;
  double worst = 1e9;
  for (const auto& preset : presets) {
    const Result r = Measure(preset, episodes, repeats);
    results.push_back(r);
    worst = std::min(worst, r.env_rate / r.bare_rate);
    std::printf("%-26s %12.1f %12.1f %8.3f %14.0f\n", r.preset.c_str(), r.env_rate, r.bare_rate,
                r.env_rate / r.bare_rate, r.bare_rate * r.frame_skip);
    std::fflush(stdout);
  }
  std::printf("\ntarget: env >= 0.90 x bare; worst ratio %.3f\n", worst);
  std::string json = "{\"bench\":\"env\",\"episodes\":" + std::to_string(episodes) +
                     ",\"steps_per_episode\":" + std::to_string(kEpisodeSteps) +
                     ",\"repeats\":" + std::to_string(repeats) + ",\"presets\":{";
  for (size_t i = 0; i < results.size(); ++i) {
    char item[256];
    std::snprintf(item, sizeof(item), "%s\"%s\":{\"env_steps_per_s\":%.1f,\"bare_steps_per_s\":%.1f,\"ratio\":%.4f}",
                  i ? "," : "", results[i].preset.c_str(), results[i].env_rate, results[i].bare_rate,
                  results[i].env_rate / results[i].bare_rate);
    json += item;
  }
  char tail[64];
  std::snprintf(tail, sizeof(tail), "},\"ratio\":%.4f}", worst);
  std::printf("%s%s\n", json.c_str(), tail);
  return 0;
}
