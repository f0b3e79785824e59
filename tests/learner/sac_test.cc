#include "learner/sac.h"

#include <gtest/gtest.h>

#include <malloc.h>
#include <sys/resource.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <optional>
#include <utility>

#include "common/nn/serialize.h"
#include "common/process/memory.h"
#include "tests/sanitizer.h"

namespace srics::learner {
namespace {

// A small agent: two entities of 4 floats, goal tokens of 5, 2 actions.
config::AgentConfig SmallConfig() {
  config::AgentConfig c;
  c.network.embed_dim = 16;
  c.network.heads = 2;
  c.network.policy_hidden = {32, 32};
  c.network.q_hidden = {32, 32};
  c.sac.batch_size = 64;
  return c;
}

const AgentShape kShape{4, 5, 2};

// A batch of random states and goals; actions uniform in [-1, 1]; reward from `reward(a)`.
TrainingBatch RandomBatch(std::mt19937_64& rng, int size, double (*reward)(const float*)) {
  TrainingBatch b;
  b.size = size;
  b.max_entities = 2;
  b.entity_dim = 4;
  b.goal_dim = 5;
  b.action_dim = 2;
  std::uniform_real_distribution<float> u(-1, 1);
  for (int i = 0; i < size * 2 * 4; ++i) {
    b.entities.push_back(u(rng));
    b.next_entities.push_back(u(rng));
  }
  b.mask.assign(size * 2, 1.0f);
  for (int i = 0; i < size * 5; ++i) b.goal.push_back(u(rng));
  for (int i = 0; i < size; ++i) {
    const float a[2] = {u(rng), u(rng)};
    b.action.insert(b.action.end(), a, a + 2);
    b.reward.push_back(static_cast<float>(reward(a)));
  }
  b.subgoal_entity.assign(size, 0);
  return b;
}

// The stats after 1500 updates on r = -1 forever with discount 0.9 and no entropy bonus
// (Q = -1 / (1 - 0.9) = -10), the targets clipped into `bound` when given.
UpdateStats TrainOnAConstantReward(std::optional<std::pair<float, float>> bound) {
  config::AgentConfig c = SmallConfig();
  c.sac.discount = 0.9;
  c.sac.auto_entropy = false;
  c.sac.initial_alpha = 1e-8;
  SacAgent agent(kShape, c, 1, 1);
  if (bound) agent.BoundTargets(bound->first, bound->second);
  std::mt19937_64 rng(2);
  UpdateStats stats;
  for (int i = 0; i < 1500; ++i) stats = agent.Update(RandomBatch(rng, 64, [](const float*) { return -1.0; }));
  return stats;
}

TEST(SacTest, CriticsConvergeToTheDiscountedReturnOfAConstantReward) {
  const UpdateStats stats = TrainOnAConstantReward(std::nullopt);
  EXPECT_NEAR(stats.mean_q, -10.0, 0.5);
  EXPECT_LT(stats.q_loss, 0.05);
}

// HAC's bound: targets clipped into [-4, 0]. r = -1 forever with discount 0.9 would give
// -10; bounded, the critics learn the bound instead (and stay at it).
TEST(SacTest, BoundedTargetsKeepTheCriticsInTheBound) {
  const UpdateStats stats = TrainOnAConstantReward(std::make_pair(-4.0f, 0.0f));
  EXPECT_NEAR(stats.mean_q, -4.0, 0.3);
  EXPECT_LT(stats.q_loss, 0.05);
  SacAgent agent(kShape, SmallConfig(), 1, 1);
  EXPECT_THROW(agent.BoundTargets(1.0f, 0.0f), std::invalid_argument);
}

// Issue 15: a non-finite value in a batch (huge finite states overflow the networks the same
// way) turned every weight into NaN and the learner published them. Now the update stops
// before the optimizer step of the stage where it shows: no network changes.
TEST(SacTest, NonFiniteBatchChangesNoNetwork) {
  // with 2 threads the poisoned samples lie in either shard (rows 0-31: the calling thread's)
  for (int threads : {1, 2}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    SacAgent agent(kShape, SmallConfig(), 1, threads);
    std::mt19937_64 rng(3);
    for (int i = 0; i < 5; ++i)
      EXPECT_FALSE(agent.Update(RandomBatch(rng, 64, [](const float*) { return 0.5; })).non_finite);
    const std::vector<float> policy_before = agent.PolicyWeights();
    const std::vector<float> q1_before = nn::Flatten(agent.q1().Parameters());
    const double alpha_before = agent.alpha();

    TrainingBatch poisoned = RandomBatch(rng, 64, [](const float*) { return 0.5; });
    poisoned.reward[7] = std::numeric_limits<float>::quiet_NaN();  // the Bellman targets
    UpdateStats skipped = agent.Update(poisoned);
    EXPECT_TRUE(skipped.non_finite);
    EXPECT_EQ(skipped.non_finite_stage, "critic targets");
    poisoned = RandomBatch(rng, 64, [](const float*) { return 0.5; });
    poisoned.entities[11] = std::numeric_limits<float>::infinity();  // the critics' loss and gradients
    skipped = agent.Update(poisoned);
    EXPECT_TRUE(skipped.non_finite);
    EXPECT_EQ(skipped.non_finite_stage, "critic loss or gradient");
    poisoned = RandomBatch(rng, 64, [](const float*) { return 0.5; });
    poisoned.reward[3] = 3e38f;  // finite, but its square overflows the critics' loss
    skipped = agent.Update(poisoned);
    EXPECT_TRUE(skipped.non_finite);
    EXPECT_EQ(skipped.non_finite_stage, "critic loss or gradient");
    poisoned = RandomBatch(rng, 64, [](const float*) { return 0.5; });
    poisoned.entities[13] = 1e12f;  // finite everywhere, but gradients whose squares overflow Adam's moments
    skipped = agent.Update(poisoned);
    EXPECT_TRUE(skipped.non_finite);
    EXPECT_EQ(skipped.non_finite_stage, "critic loss or gradient");
    poisoned = RandomBatch(rng, 64, [](const float*) { return 0.5; });
    poisoned.reward[50] = std::numeric_limits<float>::quiet_NaN();  // the second shard's targets
    skipped = agent.Update(poisoned);
    EXPECT_TRUE(skipped.non_finite);
    EXPECT_EQ(skipped.non_finite_stage, "critic targets");

    EXPECT_EQ(agent.PolicyWeights(), policy_before);
    EXPECT_EQ(nn::Flatten(agent.q1().Parameters()), q1_before);
    EXPECT_EQ(agent.alpha(), alpha_before);
    // and the agent goes on learning from good batches
    const UpdateStats next = agent.Update(RandomBatch(rng, 64, [](const float*) { return 0.5; }));
    EXPECT_FALSE(next.non_finite);
    EXPECT_TRUE(std::isfinite(next.q_loss));
    EXPECT_NE(agent.PolicyWeights(), policy_before);
  }
}

TEST(SacTest, PolicyMovesToTheBestActionOfTheCritic) {
  // a one-step problem (discount 0): the best action is (0.5, -0.3)
  config::AgentConfig c = SmallConfig();
  c.sac.discount = 0.0;
  SacAgent agent(kShape, c, 3, 1);
  std::mt19937_64 rng(4);
  auto reward = [](const float* a) { return -4.0 * ((a[0] - 0.5) * (a[0] - 0.5) + (a[1] + 0.3) * (a[1] + 0.3)); };
  for (int i = 0; i < 2000; ++i) agent.Update(RandomBatch(rng, 64, reward));
  nn::Rng act_rng(5);
  double error = 0;
  const int trials = 20;
  for (int i = 0; i < trials; ++i) {
    TrainingBatch probe = RandomBatch(rng, 1, reward);
    nn::Tensor entities = Eigen::Map<nn::Tensor>(probe.entities.data(), 2, 4);
    nn::Tensor goal = Eigen::Map<nn::Tensor>(probe.goal.data(), 1, 5);
    const nn::Tensor& a = agent.policy().Act(entities, goal, true, act_rng);
    error += std::hypot(a(0, 0) - 0.5, a(0, 1) + 0.3);
  }
  EXPECT_LT(error / trials, 0.1);
  // the temperature fell: the policy's entropy went towards the target
  EXPECT_LT(agent.alpha(), 0.5);
}

TEST(SacTest, CheckpointRoundTripRestoresNetworksOptimizersAndCounters) {
  const std::string path = ::testing::TempDir() + "/sac_round_trip.srics";
  SacAgent a(kShape, SmallConfig(), 10, 1);
  std::mt19937_64 rng(11);
  for (int i = 0; i < 30; ++i) a.Update(RandomBatch(rng, 64, [](const float* x) { return double(x[0]); }));
  const LearnerCounters counters{30, 12345678901ull, 77, 5};
  a.SaveCheckpoint(path, counters);

  SacAgent b(kShape, SmallConfig(), 99, 1);  // different initialisation
  EXPECT_NE(a.PolicyWeights(), b.PolicyWeights());
  EXPECT_EQ(b.LoadCheckpoint(path), counters);
  EXPECT_EQ(a.PolicyWeights(), b.PolicyWeights());
  EXPECT_EQ(nn::Flatten(a.q1().Parameters()), nn::Flatten(b.q1().Parameters()));
  EXPECT_EQ(a.alpha(), b.alpha());
  // everything, optimizer moments included, is restored: saving again gives the same sections
  const std::string again = ::testing::TempDir() + "/sac_round_trip_again.srics";
  b.SaveCheckpoint(again, counters);
  const auto first = nn::ReadCheckpoint(path);
  const auto second = nn::ReadCheckpoint(again);
  ASSERT_EQ(first.size(), second.size());
  for (size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].name, second[i].name);
    EXPECT_EQ(first[i].values, second[i].values) << first[i].name;
  }
}

TEST(SacTest, ABadCheckpointIsRefusedAndChangesNothing) {
  const std::string path = ::testing::TempDir() + "/sac_bad.srics";
  SacAgent a(kShape, SmallConfig(), 20, 1);
  a.SaveCheckpoint(path, {});
  // flip one byte in the middle: the checksum catches it
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(2000);
    char c;
    f.read(&c, 1);
    f.seekp(2000);
    c ^= 0x5a;
    f.write(&c, 1);
  }
  SacAgent b(kShape, SmallConfig(), 21, 1);
  const auto before = b.PolicyWeights();
  try {
    b.LoadCheckpoint(path);
    FAIL() << "a corrupted checkpoint was accepted";
  } catch (const nn::CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
  }
  EXPECT_EQ(b.PolicyWeights(), before);
  // another architecture: refused by name
  config::AgentConfig wider = SmallConfig();
  wider.network.policy_hidden = {48, 32};
  SacAgent c(kShape, wider, 22, 1);
  a.SaveCheckpoint(path, {});
  try {
    c.LoadCheckpoint(path);
    FAIL() << "a checkpoint of another architecture was accepted";
  } catch (const nn::CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("architecture mismatch"), std::string::npos) << e.what();
  }
}

// Relative distance of two flat vectors: |a - b| / max(|a|, tiny).
double RelativeDistance(const std::vector<float>& a, const std::vector<float>& b) {
  double diff = 0, norm = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    diff += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
    norm += double(a[i]) * a[i];
  }
  return std::sqrt(diff) / std::max(std::sqrt(norm), 1e-30);
}

std::vector<float> Grads(nn::ParameterList<float> params) {
  std::vector<float> out;
  for (const auto* p : params) out.insert(out.end(), p->grad.data(), p->grad.data() + p->grad.size());
  return out;
}

TEST(SacTest, SeveralThreadsGiveTheUpdateOfOneThreadUpToSummationOrder) {
  // the same agent (same seed) and the same batches with 1, 2 and 3 threads (64 samples split
  // 32/32 and 21/21/22): gradients, statistics and weights agree to float rounding
  for (int threads : {2, 3}) {
    SacAgent one(kShape, SmallConfig(), 7, 1);
    SacAgent many(kShape, SmallConfig(), 7, threads);
    ASSERT_EQ(many.threads(), threads);
    std::mt19937_64 rng(8);
    for (int update = 0; update < 5; ++update) {
      const TrainingBatch b = RandomBatch(rng, 64, [](const float* a) { return double(a[0] - a[1]); });
      const UpdateStats s1 = one.Update(b);
      const UpdateStats sn = many.Update(b);
      EXPECT_NEAR(sn.q_loss, s1.q_loss, 1e-5 * std::abs(s1.q_loss) + 1e-7) << threads << " threads, update " << update;
      EXPECT_NEAR(sn.policy_loss, s1.policy_loss, 1e-5 * std::abs(s1.policy_loss) + 1e-7);
      EXPECT_NEAR(sn.entropy, s1.entropy, 1e-5 * std::abs(s1.entropy) + 1e-7);
      EXPECT_NEAR(sn.mean_q, s1.mean_q, 1e-5 * std::abs(s1.mean_q) + 1e-7);
      EXPECT_NEAR(sn.alpha, s1.alpha, 1e-6 * s1.alpha);
      // the gradients of this update (left in Parameter::grad) are the whole batch's
      EXPECT_LT(RelativeDistance(Grads(many.q1().Parameters()), Grads(one.q1().Parameters())), 1e-5);
      EXPECT_LT(RelativeDistance(Grads(many.policy().Parameters()), Grads(one.policy().Parameters())), 1e-5);
      // weights: Adam's first steps are about lr * sign(gradient), so an element whose gradient
      // is near zero can move differently on rounding alone; the whole stays within 1e-4
      EXPECT_LT(RelativeDistance(many.PolicyWeights(), one.PolicyWeights()), 1e-4);
      EXPECT_LT(RelativeDistance(nn::Flatten(many.q1().Parameters()), nn::Flatten(one.q1().Parameters())), 1e-4);
    }
    // and the gradients are not trivially equal because nothing was computed: they are non-zero
    double norm = 0;
    for (float g : Grads(many.q1().Parameters())) norm += double(g) * g;
    EXPECT_GT(norm, 0.0);
  }
}

// Two agents built alike, updated on the same `updates` batches of `size` (drawn from `seed`):
// the same statistics at every update and the same weights after, bit for bit.
void ExpectIdenticalUpdates(SacAgent& a, SacAgent& b, int size, uint64_t seed, int updates) {
  std::mt19937_64 rng_a(seed), rng_b(seed);
  for (int i = 0; i < updates; ++i) {
    const UpdateStats sa = a.Update(RandomBatch(rng_a, size, [](const float* x) { return double(x[1]); }));
    const UpdateStats sb = b.Update(RandomBatch(rng_b, size, [](const float* x) { return double(x[1]); }));
    EXPECT_EQ(sa.q_loss, sb.q_loss) << "update " << i;
    EXPECT_EQ(sa.policy_loss, sb.policy_loss) << "update " << i;
  }
  EXPECT_EQ(a.PolicyWeights(), b.PolicyWeights());
  EXPECT_EQ(nn::Flatten(a.q2().Parameters()), nn::Flatten(b.q2().Parameters()));
}

TEST(SacTest, UpdatesWithTwoThreadsAreDeterministic) {
  SacAgent a(kShape, SmallConfig(), 12, 2);
  SacAgent b(kShape, SmallConfig(), 12, 2);
  ExpectIdenticalUpdates(a, b, 64, 13, 10);
}

// learner.precision bf16: the paper's network sizes (products large enough for oneDNN), the
// same agent and batches in fp32 and bf16. bf16 rounds each product's operands to 8 bits of
// mantissa: the update's statistics and gradients stay within a few per cent, and differ.
config::AgentConfig PaperSizedConfig() {
  config::AgentConfig c;  // embed 80 in 5 heads, policy [128, 128], Q [128, 128, 128]
  c.sac.batch_size = 512;
  return c;
}

TEST(SacTest, Bf16ProductsGiveTheFp32UpdateWithinBfloat16Rounding) {
  SacAgent fp32(kShape, PaperSizedConfig(), 31, 1);
  SacAgent bf16(kShape, PaperSizedConfig(), 31, 1);
  const nn::GemmPrecision effective = bf16.SetProductPrecision(nn::GemmPrecision::kBf16);
  EXPECT_EQ(effective, nn::Bf16ProductsAvailable() ? nn::GemmPrecision::kBf16 : nn::GemmPrecision::kFp32);
  if (effective != nn::GemmPrecision::kBf16) GTEST_SKIP() << "no bf16 products on this CPU";
  std::mt19937_64 rng(32);
  for (int update = 0; update < 3; ++update) {
    const TrainingBatch b = RandomBatch(rng, 512, [](const float* a) { return double(a[0] - a[1]); });
    const UpdateStats s32 = fp32.Update(b);
    const UpdateStats s16 = bf16.Update(b);
    EXPECT_NEAR(s16.q_loss, s32.q_loss, 0.03 * std::abs(s32.q_loss)) << "update " << update;
    EXPECT_NEAR(s16.policy_loss, s32.policy_loss, 0.03 * std::abs(s32.policy_loss) + 1e-3);
    EXPECT_NEAR(s16.mean_q, s32.mean_q, 0.03 * std::abs(s32.mean_q) + 1e-3);
    const double q_grads = RelativeDistance(Grads(bf16.q1().Parameters()), Grads(fp32.q1().Parameters()));
    const double policy_grads = RelativeDistance(Grads(bf16.policy().Parameters()), Grads(fp32.policy().Parameters()));
    EXPECT_LT(q_grads, 0.05) << "update " << update;
    EXPECT_LT(policy_grads, 0.1) << "update " << update;
    EXPECT_GT(q_grads, 1e-6) << "the bf16 agent computed in fp32";
  }
}

// Sets both agents' products to bf16; false on a CPU without them.
bool BothInBf16(SacAgent& a, SacAgent& b) {
  if (a.SetProductPrecision(nn::GemmPrecision::kBf16) != nn::GemmPrecision::kBf16) return false;
  b.SetProductPrecision(nn::GemmPrecision::kBf16);
  return true;
}

TEST(SacTest, Bf16UpdatesWithTwoThreadsAreDeterministic) {
  SacAgent a(kShape, PaperSizedConfig(), 41, 2);
  SacAgent b(kShape, PaperSizedConfig(), 41, 2);
  if (!BothInBf16(a, b)) GTEST_SKIP() << "no bf16 products on this CPU";
  ExpectIdenticalUpdates(a, b, 512, 42, 3);
}

// The worker threads' shards run in bf16 too: two threads give the one-thread bf16 update up
// to summation order (a shard left in fp32 would differ by bf16's rounding, ~1000 times more).
TEST(SacTest, Bf16ReachesEveryShardThread) {
  SacAgent one(kShape, PaperSizedConfig(), 51, 1);
  SacAgent two(kShape, PaperSizedConfig(), 51, 2);
  if (!BothInBf16(one, two)) GTEST_SKIP() << "no bf16 products on this CPU";
  std::mt19937_64 rng(52);
  const TrainingBatch b = RandomBatch(rng, 512, [](const float* a) { return double(a[0]); });
  one.Update(b);
  two.Update(b);
  EXPECT_LT(RelativeDistance(Grads(two.q1().Parameters()), Grads(one.q1().Parameters())), 1e-4);
  EXPECT_LT(RelativeDistance(Grads(two.policy().Parameters()), Grads(one.policy().Parameters())), 1e-4);
}

TEST(SacTest, ABatchSmallerThanTheThreadCountStillUpdates) {
  // 3 threads, 2 samples: one shard per sample, the third thread idles
  SacAgent one(kShape, SmallConfig(), 14, 1);
  SacAgent many(kShape, SmallConfig(), 14, 3);
  std::mt19937_64 rng(15);
  const TrainingBatch b = RandomBatch(rng, 2, [](const float*) { return 1.0; });
  const UpdateStats s1 = one.Update(b);
  const UpdateStats sn = many.Update(b);
  EXPECT_NEAR(sn.q_loss, s1.q_loss, 1e-5 * std::abs(s1.q_loss) + 1e-7);
  EXPECT_LT(RelativeDistance(Grads(many.q2().Parameters()), Grads(one.q2().Parameters())), 1e-5);
  EXPECT_LT(RelativeDistance(Grads(many.policy().Parameters()), Grads(one.policy().Parameters())), 1e-5);
  EXPECT_LT(RelativeDistance(many.PolicyWeights(), one.PolicyWeights()), 1e-4);
}

// An update records the same ops with the same shapes every time, so after the first one it
// finds every buffer it needs on its tapes. With one tape for the three passes (targets,
// critics, policy) most buffers changed shape from pass to pass and were reallocated: ~30% of a
// batch-2048 run's CPU time when those were mapped on their own (page faults, munmaps). Here
// every block of 1 MiB or more is mapped on its own for the test's length, so that any
// reallocation of the update's buffers (over 1 MiB at 16,384 samples) shows as page faults:
// 16,644 per update with one tape, none with a tape per pass.
TEST(SacTest, UpdatesAfterTheFirstReuseTheirBuffers) {
#ifdef SRICS_TESTING_ASAN
  GTEST_SKIP() << "AddressSanitizer's allocator replaces glibc's heap and its settings";
#endif
  process::SetUpHeap();
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  SacAgent agent(kShape, SmallConfig(), 21, 1);
  std::mt19937_64 rng(22);
  const TrainingBatch b = RandomBatch(rng, 16384, [](const float* a) { return double(a[0]); });
  agent.Update(b);
  agent.Update(b);
  auto minor_faults = [] {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_minflt;
  };
  const long before = minor_faults();
  constexpr int kUpdates = 3;
  for (int i = 0; i < kUpdates; ++i) agent.Update(b);
  const long per_update = (minor_faults() - before) / kUpdates;
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(process::kHeapMmapThreshold));  // the policy again
  // one 16,384 x 16 float buffer alone is 256 pages
  EXPECT_LT(per_update, 64) << "page faults per update";
}

}  // namespace
}  // namespace srics::learner
