// HAC on the actor's side, with the real environment and networks: the training episode's
// subgoal record, the actor loop splitting published weights into the two levels, and the
// evaluation running both levels on the full goal.

#include <gtest/gtest.h>

#include <cmath>

#include "actor/actor_loop.h"
#include "actor/env/rearrange_env.h"
#include "common/links/in_memory_bus.h"
#include "common/nn/serialize.h"
#include "common/rl/agent_shape.h"

namespace srics::actor {
namespace {

config::Config HacConfig() {
  return config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml",
                            {"run.method=hac", "agent.hac.horizon=4", "actors.eval_episodes=2"});
}

TEST(HacRolloutTest, TrainingEpisodeRecordsHSubgoalsOfAtMostHSteps) {
  const config::Config config = HacConfig();
  const ActorOptions options = ActorOptionsFor(config, rl::RunShapeFor(config), 0);
  ASSERT_TRUE(options.high_policy.has_value());
  ASSERT_TRUE(options.train.hac.has_value());
  EXPECT_EQ(options.train.steps, 16);
  EXPECT_EQ(options.high_policy->action_dim, 4);  // the xy of the arm and the puck
  EXPECT_EQ(options.policy.goal_dim, 4);
  nn::Rng rng(5);
  rl::PolicyNetwork<float> high("policy", *options.high_policy, rng), low("policy", options.policy, rng);
  auto env = env::MakeRearrangeEnv(config.env);
  // always tested: the low level takes its mean action
  HacActOptions act = *options.train.hac;
  act.test_probability = 1.0;
  const auto e = RunHacTrainEpisode(*env, high, low, act, 7, rng);
  ASSERT_TRUE(e.has_value());
  rl::EpisodeLimits limits = rl::EpisodeLimitsFor(config.env);
  limits.max_subgoal_steps = 4;
  EXPECT_EQ(rl::ValidateEpisode(*e, limits), "");
  ASSERT_EQ(e->num_subgoals(), 4);
  EXPECT_EQ(e->goal.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(e->subgoal_tests[k], 1);
    const int length = e->subgoal_end(k) - e->subgoal_start(k);
    // an attempt ends after H steps or where its subgoal (or the full goal) is reached
    EXPECT_TRUE(length == 4 || rl::GoalReached(e->layout, e->state(e->subgoal_end(k)), e->subgoal(k), act.threshold) ||
                rl::GoalReached(e->layout, e->state(e->subgoal_end(k)), e->goal.data(), act.threshold))
        << "attempt " << k << " of " << length << " steps";
    for (int j = 0; j < 4; ++j) {
      const float v = e->subgoal(k)[j];
      EXPECT_TRUE(j % 2 == 0 ? std::fabs(v) <= 0.25f : v >= 0.35f && v <= 0.76f) << v;
    }
  }
  // never tested: the same seeds act with noise, so the episode differs
  act.test_probability = 0.0;
  nn::Rng rng2(5);
  rl::PolicyNetwork<float> high2("policy", *options.high_policy, rng2), low2("policy", options.policy, rng2);
  const auto noisy = RunHacTrainEpisode(*env, high2, low2, act, 7, rng2);
  ASSERT_TRUE(noisy.has_value());
  for (uint8_t t : noisy->subgoal_tests) EXPECT_EQ(t, 0);
}

TEST(HacRolloutTest, ActorSplitsTheWeightsIntoBothLevelsAndEvaluatesOnTheFullGoal) {
  const config::Config config = HacConfig();
  links::InMemoryBus bus;
  auto link = bus.ActorEnd(0);
  auto learner = bus.LearnerEnd();
  const ActorOptions options = ActorOptionsFor(config, rl::RunShapeFor(config), 0);
  ActorLoop actor(options, link.get());
  nn::Rng rng(3);
  rl::PolicyNetwork<float> high("policy", *options.high_policy, rng), low("policy", options.policy, rng);
  std::vector<float> flat = nn::Flatten(high.Parameters());
  const std::vector<float> low_flat = nn::Flatten(low.Parameters());
  flat.insert(flat.end(), low_flat.begin(), low_flat.end());
  // the low level's weights alone (a flat method's) are refused
  learner->PublishWeights({1, 10, rl::PolicySignature(low), low_flat});
  ASSERT_EQ(actor.Step(), StepResult::kWorked);
  EXPECT_EQ(actor.counters().weights_rejected, 1u);
  learner->PublishWeights({2, 20, rl::HacPolicySignature(high, low), flat});
  // the passive evaluation first, then a HAC training episode with these weights
  ASSERT_EQ(actor.Step(), StepResult::kWorked);
  ASSERT_EQ(actor.Step(), StepResult::kWorked);
  EXPECT_EQ(actor.counters().weights_rejected, 1u);
  EXPECT_EQ(actor.policy_version(), 2u);
  std::vector<rl::Episode> episodes;
  learner->TakeEpisodes(&episodes, 100, std::chrono::milliseconds(0));
  ASSERT_FALSE(episodes.empty());
  EXPECT_EQ(episodes.back().mode, rl::EpisodeMode::kTrain);
  EXPECT_EQ(episodes.back().policy_version, 2u);
  EXPECT_EQ(episodes.back().num_subgoals(), 4);

  // evaluation with both levels: deterministic, finite, and it moves the arm (passive does not)
  auto env = env::MakeRearrangeEnv(config.env);
  uint64_t unstable = 0;
  const rl::CatalogueSubgoals all;  // no graph: every entity
  const auto a = EvaluatePolicy(*env, &low, all, options.eval, 2, 1, &unstable, &high);
  const auto b = EvaluatePolicy(*env, &low, all, options.eval, 2, 1, &unstable, &high);
  const auto passive = EvaluatePolicy(*env, nullptr, all, options.eval, 2, 1, &unstable);
  EXPECT_EQ(unstable, 0u);
  EXPECT_EQ(a.episodes, 2);
  EXPECT_TRUE(std::isfinite(a.avg_distance));
  EXPECT_EQ(a.avg_distance, b.avg_distance);
  EXPECT_NE(a.entity_distance[0], passive.entity_distance[0]);
  EXPECT_THROW(EvaluatePolicy(*env, &low, all, options.eval, 1, 1, &unstable), std::invalid_argument);
}

}  // namespace
}  // namespace srics::actor
