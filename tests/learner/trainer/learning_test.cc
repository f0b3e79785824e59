// The learning test of the suite: SRICS trained in process on Rearrange 1 for a few thousand
// steps must reach arm subgoals (random goals in the subgoal region) in at least 90% of
// evaluation episodes, which the passive policy almost never does.

#include <gtest/gtest.h>

#include <filesystem>

#include "actor/env/rearrange_env.h"
#include "actor/env/sampling.h"
#include "common/config/config.h"
#include "common/nn/serialize.h"
#include "common/rl/goal_token.h"
#include "learner/learner.h"
#include "learner/trainer/in_process_trainer.h"

namespace srics::trainer {
namespace {

// Fraction of episodes whose arm ends within `threshold` of a random arm goal after `steps`
// deterministic steps; `policy` null = passive.
double ArmSubgoalSuccess(const config::Config& config, rl::PolicyNetwork<float>* policy,
                         int episodes) {
  auto env = env::MakeRearrangeEnv(config.env);
  env::Rng goal_rng(4242);
  nn::Rng act_rng(1);
  int solved = 0;
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
                                states.data(), env->layout().num_entities, env->layout().state_dim)
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
    solved += std::hypot(arm[0] - goal[0], arm[1] - goal[1]) < config.env.success_threshold;
  }
  return static_cast<double>(solved) / episodes;
}

TEST(LearningTest, SricsLearnsToReachArmSubgoals) {
  const std::string dir = ::testing::TempDir() + "/learning_test";
  std::filesystem::remove_all(dir);
  config::Config config = config::LoadConfig(
      std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml",
      {"run.total_env_steps=10000", "learner.warmup_steps=1000", "agent.sac.batch_size=128",
       "actors.eval_every_env_steps=100000", "actors.eval_episodes=5", "run.max_wall_minutes=2.5"});
  TrainerOptions options;
  options.run_dir = dir;
  const TrainResult result = TrainInProcess(config, options);
  EXPECT_GE(result.env_steps, 3000u) << "too few steps within the wall-clock limit";
  EXPECT_EQ(result.unstable_episodes, 0u);

  // the trained policy, from the run's checkpoint
  learner::Learner restored(config);
  restored.LoadCheckpoint(dir + "/checkpoint.srics");
  EXPECT_EQ(restored.counters().updates, result.updates);
  const double trained = ArmSubgoalSuccess(config, &restored.agent().policy(), 50);
  const double passive = ArmSubgoalSuccess(config, nullptr, 50);
  RecordProperty("trained_success", std::to_string(trained));
  RecordProperty("passive_success", std::to_string(passive));
  std::printf("arm subgoal success: trained %.2f, passive %.2f (%llu steps, %llu updates, %.0f s)\n",
              trained, passive, (unsigned long long)result.env_steps,
              (unsigned long long)result.updates, result.wall_seconds);
  EXPECT_GE(trained, 0.9);
  EXPECT_LE(passive, 0.2);
}

}  // namespace
}  // namespace srics::trainer
