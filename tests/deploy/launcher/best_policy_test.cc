// best.srics: the weights of the evaluation with the lowest average distance, written when an
// evaluation beats the best so far, loadable as srics eval loads a checkpoint; a resumed run
// keeps its best.

#include "deploy/launcher/best_policy.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "actor/actor_loop.h"
#include "common/nn/serialize.h"
#include "common/rl/agent_shape.h"
#include "learner/acting_policy.h"
#include "tests/common/files/test_files.h"

namespace srics::launcher {
namespace {

namespace fs = std::filesystem;
using files::testing::ReadFile;

class BestPolicyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    config_ = config::LoadConfig(std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml", {});
    net_ = std::make_unique<rl::PolicyNetwork<float>>(
        "policy", actor::ActorOptionsFor(config_, rl::RunShapeFor(config_), 0).policy, rng_);
    signature_ = rl::PolicySignature(*net_);
  }

  // Weights of version v: the network's initial parameters shifted by v.
  std::vector<float> Weights(uint64_t v) {
    std::vector<float> w = nn::Flatten(net_->Parameters());
    for (float& x : w) x += 0.001f * static_cast<float>(v);
    return w;
  }
  // The policy in best.srics, as srics eval loads it, and its counters.
  std::pair<std::vector<float>, learner::LearnerCounters> Load() {
    nn::Rng rng(7);
    rl::PolicyNetwork<float> policy("policy", actor::ActorOptionsFor(config_, rl::RunShapeFor(config_), 0).policy, rng);
    const learner::LearnerCounters counters =
        learner::LoadActingPolicies((dir_ / "best.srics").string(), policy, nullptr);
    return {nn::Flatten(policy.Parameters()), counters};
  }

  files::testing::ScratchFolder dir_{"srics_best_policy_test"};
  config::Config config_;
  nn::Rng rng_{3};
  std::unique_ptr<rl::PolicyNetwork<float>> net_;
  std::string signature_;
};

TEST_F(BestPolicyTest, KeepsTheWeightsOfTheLowestAverageDistance) {
  BestPolicy best(config_, dir_.string(), /*kept_bytes=*/0);  // keeps kMinKeptVersions
  best.OnWeights(1, 10, signature_, Weights(1));
  best.OnWeights(2, 20, signature_, Weights(2));
  EXPECT_FALSE(best.OnEval(0, 0, 0.05)) << "the passive policy never counts";
  EXPECT_FALSE(fs::exists(dir_ / "best.srics"));

  const auto first = best.OnEval(1, 1000, 0.30);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->policy_version, 1u);
  EXPECT_EQ(Load().first, Weights(1));
  EXPECT_FALSE(best.OnEval(2, 2000, 0.35)) << "worse than the best";
  EXPECT_FALSE(best.OnEval(2, 2000, 0.30)) << "only a lower distance replaces it";
  EXPECT_EQ(Load().first, Weights(1));

  // weights of another network are not kept; only the last kMinKeptVersions versions are here
  best.OnWeights(3, 30, "another network", Weights(3));
  EXPECT_FALSE(best.OnEval(3, 3000, 0.1));
  for (uint64_t v = 3; v <= 7; ++v) best.OnWeights(v, 10 * v, signature_, Weights(v));
  EXPECT_FALSE(best.OnEval(2, 2500, 0.1)) << "v2's weights are no longer kept";
  const auto second = best.OnEval(7, 7000, 0.2);
  ASSERT_TRUE(second);
  const auto [weights, counters] = Load();
  EXPECT_EQ(weights, Weights(7));
  EXPECT_EQ(counters.policy_version, 7u);
  EXPECT_EQ(counters.updates, 70u);
  EXPECT_EQ(counters.training_env_steps, 7000u);
  const auto yaml = ParseBestEvaluation(ReadFile(dir_ / "best.yaml"));
  ASSERT_TRUE(yaml);
  EXPECT_EQ(yaml->policy_version, 7u);
  EXPECT_EQ(yaml->update_count, 70u);
  EXPECT_EQ(yaml->env_steps, 7000u);
  EXPECT_DOUBLE_EQ(yaml->avg_distance, 0.2);
  EXPECT_FALSE(fs::exists(dir_ / "best.srics.tmp")) << "written aside and renamed";
}

TEST_F(BestPolicyTest, AResumedRunReplacesItsBestOnlyWithABetterEvaluation) {
  {
    BestPolicy best(config_, dir_.string());
    best.OnWeights(4, 40, signature_, Weights(4));
    ASSERT_TRUE(best.OnEval(4, 4000, 0.2));
  }
  BestPolicy resumed(config_, dir_.string());
  ASSERT_TRUE(resumed.best());
  EXPECT_EQ(resumed.best()->policy_version, 4u);
  resumed.OnWeights(5, 50, signature_, Weights(5));
  EXPECT_FALSE(resumed.OnEval(5, 5000, 0.25));
  EXPECT_EQ(Load().first, Weights(4));
  resumed.OnWeights(6, 60, signature_, Weights(6));
  EXPECT_TRUE(resumed.OnEval(6, 6000, 0.15));
  EXPECT_EQ(Load().first, Weights(6));
}

TEST(BestEvaluationTest, YamlRoundTripAndGarbage) {
  const BestEvaluation best{12, 3400, 56000, 0.123456789};
  const auto back = ParseBestEvaluation(BestEvaluationYaml(best));
  ASSERT_TRUE(back);
  EXPECT_EQ(back->policy_version, 12u);
  EXPECT_EQ(back->update_count, 3400u);
  EXPECT_EQ(back->env_steps, 56000u);
  EXPECT_DOUBLE_EQ(back->avg_distance, 0.123456789);
  EXPECT_FALSE(ParseBestEvaluation("policy_version: 3\n"));
  EXPECT_FALSE(ParseBestEvaluation("policy_version: 3\nupdate_count: 1\nenv_steps: 2\navg_distance: x\n"));
}

// The default run publishes weights every 50 updates at about 160 updates/s, and an evaluation
// reports its version 5-60 versions later: with the last 4 versions kept, most of its best
// evaluations could not be copied ("weights are no longer kept", 2026-12-07). Versions are kept
// within a byte budget: a small network's evaluation 100 versions back is still copied, and
// the budget holds (the oldest go first, never fewer than kMinKeptVersions).
TEST_F(BestPolicyTest, KeepsEnoughVersionsForAnEvaluationThatArrivesLate) {
  const size_t version_bytes = Weights(1).size() * sizeof(float);
  BestPolicy best(config_, dir_.string(), /*kept_bytes=*/150 * version_bytes);
  for (uint64_t v = 1; v <= 200; ++v) best.OnWeights(v, 10 * v, signature_, Weights(v));
  const auto late = best.OnEval(100, 5000, 0.2);
  ASSERT_TRUE(late) << "v100 is 100 versions back";
  EXPECT_EQ(Load().first, Weights(100));
  EXPECT_FALSE(best.OnEval(40, 2000, 0.1)) << "v40 is beyond the budget of 150 versions";
  EXPECT_GE(BestPolicy::kKeptBytes, 100 * size_t{260000}) << "the default run's 0.26 MB policy, 100 versions";
}

}  // namespace
}  // namespace srics::launcher
