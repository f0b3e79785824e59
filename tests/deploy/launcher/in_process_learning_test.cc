// The learning test of the suite: SRICS run in process (the distributed run's loops wired in
// memory) on Rearrange 1 for a few thousand steps reaches arm subgoals in most episodes, which
// the passive policy almost never does.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include "actor/env/rearrange_env.h"
#include "actor/env/sampling.h"
#include "common/nn/serialize.h"
#include "common/rl/goal_token.h"
#include "deploy/launcher/in_process_run.h"
#include "learner/learner.h"

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;

std::string Config(const std::string& name) { return std::string(SRICS_SOURCE_DIR) + "/deploy/configs/" + name; }

struct ArmReach {
  double success = 0;        // fraction of episodes ending within the success threshold
  double mean_distance = 0;  // mean final distance of the arm to its goal
};

// The learner's trained policy on random arm goals after train_episode_steps deterministic
// steps (`policy` null: passive).
ArmReach ArmSubgoalSuccess(const config::Config& config, rl::PolicyNetwork<float>* policy, int episodes) {
  auto env = env::MakeRearrangeEnv(config.env);
  env::Rng goal_rng(4242);
  nn::Rng act_rng(1);
  int solved = 0;
  double distance = 0;
  std::vector<double> states;
  for (int e = 0; e < episodes; ++e) {
    env->Reset(900000 + e);
    const env::Vec2 goal = env::SampleSubgoal(config.env.sampling, goal_rng);
    const int kinds = env->layout().num_kinds;
    nn::Tensor token(1, rl::SubgoalTokenSize(kinds));
    rl::WriteSubgoalToken(kinds, 0, goal[0], goal[1], token.data());
    for (int t = 0; t < config.actors.train_episode_steps; ++t) {
      env->GetStates(&states);
      nn::Tensor entities = Eigen::Map<Eigen::Matrix<double, -1, -1, Eigen::RowMajor>>(
                                states.data(), env->layout().num_entities, env->layout().entity_dim)
                                .cast<float>();
      double action[2] = {0, 0};
      if (policy) {
        const nn::Tensor& a = policy->Act(entities, token, true, act_rng);
        action[0] = a(0, 0);
        action[1] = a(0, 1);
      }
      env->Step(action);
    }
    const env::Vec2 arm = env->Positions()[0];
    const double d = std::hypot(arm[0] - goal[0], arm[1] - goal[1]);
    solved += d < config.env.success_threshold;
    distance += d;
  }
  return {static_cast<double>(solved) / episodes, distance / episodes};
}

// SRICS in process on Rearrange 1 (its ground-truth graph: the RL part alone) for 5000 steps
// reaches arm subgoals in most episodes; the passive policy hardly. (This deterministic run
// measured 0.88 at 4000 steps, 0.76 at 5000, 0.68 at 7000 on the AMD machine, while the run's
// own evaluation had the puck's subgoal improving: the bar is "clearly learned", not a peak.)
// With one thread and with two (run.in_process_threads: the learner beside the actors, a run of
// its own).
class InProcessLearningTest : public ::testing::TestWithParam<int> {};

TEST_P(InProcessLearningTest, SricsLearnsToReachArmSubgoals) {
  const std::string dir = ::testing::TempDir() + "/in_process_learning_" + std::to_string(GetParam());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const config::Config config =
      config::LoadConfig(Config("rearrange-1-cpu.yaml"),
                         {"graph.ground_truth=true", "run.total_env_steps=5000", "learner.warmup_steps=1000",
                          "agent.sac.batch_size=128", "actors.count=1", "actors.eval_every_env_steps=100000",
                          "actors.eval_episodes=5", "run.in_process_threads=" + std::to_string(GetParam())});
  // the in-process run is deterministic: a step budget, not a time limit, so a loaded machine
  // takes longer but learns the same (a 150 s limit failed with 3690 steps under load 6)
  InProcessRun run(config, dir, nullptr);
  while (run.Round()) {
  }

  learner::Learner restored(learner::LearnerOptionsFor(config, rl::RunShapeFor(config)));
  restored.LoadCheckpoint(dir + "/checkpoint.srics");
  EXPECT_GE(restored.counters().transitions_inserted, 5000u);
  const ArmReach trained = ArmSubgoalSuccess(config, &restored.agent().policy(), 50);
  const ArmReach passive = ArmSubgoalSuccess(config, nullptr, 50);
  RecordProperty("trained_success", std::to_string(trained.success));
  RecordProperty("passive_success", std::to_string(passive.success));
  std::printf(
      "arm subgoal success: trained %.2f (mean distance %.3f), passive %.2f (%.3f) (%llu transitions, %llu updates)\n",
      trained.success, trained.mean_distance, passive.success, passive.mean_distance,
      (unsigned long long)restored.counters().transitions_inserted, (unsigned long long)restored.counters().updates);
  EXPECT_GE(trained.success, 0.6);
  EXPECT_LT(trained.mean_distance, 0.5 * passive.mean_distance);
  EXPECT_LE(passive.success, 0.2);
}

INSTANTIATE_TEST_SUITE_P(InProcessRunTest, InProcessLearningTest, ::testing::Values(1, 2),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return std::to_string(info.param) + "_threads";
                         });

}  // namespace
}  // namespace srics::launcher
