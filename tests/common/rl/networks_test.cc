// The SAC attention networks: gradients against finite differences (double), invariance to
// entity order and padding, mixed entity counts in one batch, and the actor fast path.
#include "common/rl/networks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "common/nn/optim.h"
#include "common/nn/serialize.h"
#include "tests/common/nn/gradcheck.h"
#include "tests/common/rl/network_configs.h"

namespace srics::rl {
namespace {

using nn::Matrix;
using nn::Parameter;
using nn::ParameterList;
using nn::Rng;
using nn::Tape;
using nn::Var;
using MatD = Matrix<double>;

constexpr double kTol = 1e-6;

using testing::PaperNetworkConfig;
using testing::SmallNetworkConfig;

// non-zero biases so that every parameter matters in the checks
template <typename T>
void RandomizeBiases(const ParameterList<T>& params, Rng& rng) {
  for (Parameter<T>* p : params) {
    if (p->value.rows() == 1) p->value = nn::RandomNormal<T>(1, p->value.cols(), rng) * T(0.3);
  }
}

class NetworksTest : public ::testing::Test {
 protected:
  NetworksTest() : policy_("policy", SmallNetworkConfig(), rng_), q_("q1", SmallNetworkConfig(), rng_) {
    RandomizeBiases(policy_.Parameters(), rng_);
    RandomizeBiases(q_.Parameters(), rng_);
  }
  // a batch of sets with 3, 5 and 4 entities
  EntityBatch<double> MixedBatch() {
    std::vector<MatD> sets;
    for (int n : {3, 5, 4}) sets.push_back(nn::RandomNormal<double>(n, 5, rng_));
    return PackEntities(sets, nn::RandomNormal<double>(3, 6, rng_));
  }
  Rng rng_{21};
  PolicyNetwork<double> policy_;
  QNetwork<double> q_;
};

TEST_F(NetworksTest, PolicyGradientsIncludingLogProb) {
  const auto batch = MixedBatch();
  const MatD eps = nn::RandomNormal<double>(3, 2, rng_);
  Parameter<double> ents("entities", batch.entities.rows(), batch.entities.cols());
  ents.value = batch.entities;
  ParameterList<double> vars = policy_.Parameters();
  vars.push_back(&ents);
  EXPECT_LT(nn::testing::GradCheck(vars,
                                   [&](Tape<double>& t) {
                                     auto out = policy_.Forward(t, t.Param(ents), t.Constant(batch.mask),
                                                                t.Constant(batch.goals), eps);
                                     return t.Concat({out.action, out.log_prob}, 1);
                                   }),
            kTol);
}

TEST_F(NetworksTest, QGradientsReachParametersAndActions) {
  const auto batch = MixedBatch();
  Parameter<double> actions("actions", 3, 2);
  actions.value = nn::RandomNormal<double>(3, 2, rng_).array().tanh().matrix();
  ParameterList<double> vars = q_.Parameters();
  vars.push_back(&actions);
  EXPECT_LT(nn::testing::GradCheck(vars, [&](Tape<double>& t) { return q_.Forward(t, batch, t.Param(actions)); }),
            kTol);
}

TEST_F(NetworksTest, MixedEntityCountsMatchSeparateRunsAndOrderDoesNotMatter) {
  std::vector<MatD> sets;
  for (int n : {2, 6, 4}) sets.push_back(nn::RandomNormal<double>(n, 5, rng_));
  const MatD goals = nn::RandomNormal<double>(3, 6, rng_);
  const MatD actions = nn::RandomNormal<double>(3, 2, rng_);
  Tape<double> t;
  const auto batch = PackEntities(sets, goals);
  const MatD mixed_a = policy_.Forward(t, batch, MatD::Zero(3, 2)).action.value();
  const MatD mixed_q = q_.Forward(t, batch, t.Constant(actions)).value();
  for (int b = 0; b < 3; ++b) {
    // alone, and with its entities in reverse order
    MatD reversed = sets[b].colwise().reverse();
    for (const MatD& set : {sets[b], reversed}) {
      const auto single = PackEntities<double>({set}, goals.row(b));
      t.Reset();
      const MatD a = policy_.Forward(t, single, MatD::Zero(1, 2)).action.value();
      const MatD q = q_.Forward(t, single, t.Constant(actions.row(b))).value();
      EXPECT_LT((a - mixed_a.row(b)).norm(), 1e-12);
      EXPECT_LT(std::abs(q(0, 0) - mixed_q(b, 0)), 1e-12);
    }
  }
}

TEST_F(NetworksTest, ActMatchesTapeForwardDeterministicAndSampled) {
  const MatD ents = nn::RandomNormal<double>(4, 5, rng_);
  const MatD goal = nn::RandomNormal<double>(1, 6, rng_);
  Tape<double> t;
  const auto single = PackEntities<double>({ents}, goal);
  auto mode = policy_.Forward(t, single, MatD::Zero(1, 2));
  Rng rng(5);
  const MatD act = policy_.Act(ents, goal, true, rng);
  EXPECT_LT((act - mode.action.value()).norm(), 1e-12);
  EXPECT_NEAR(policy_.last_log_prob(), mode.log_prob.value()(0, 0), 1e-9);
  // sampled: Act draws its noise as standard normals from rng, in action order
  Rng a(77), b(77);
  std::normal_distribution<double> normal(0.0, 1.0);
  MatD eps(1, 2);
  eps << normal(b), normal(b);
  t.Reset();
  auto sampled = policy_.Forward(t, single, eps);
  const MatD act2 = policy_.Act(ents, goal, false, a);
  EXPECT_LT((act2 - sampled.action.value()).norm(), 1e-12);
  EXPECT_NEAR(policy_.last_log_prob(), sampled.log_prob.value()(0, 0), 1e-9);
  EXPECT_GT((act2 - act).norm(), 1e-6);
}

// A goal of two tokens (a tied pair attempted as one): a padded second token (its constant 1
// feature 0) gives exactly the one-token network with the same parameters; two real tokens sum
// their attention outputs and goal embeddings; gradients against differences; Act as Forward.
TEST(NetworksGoalTokensTest, TwoTokensSumTheirQueriesAndAPaddedTokenChangesNothing) {
  AttentionNetworkConfig one_config = SmallNetworkConfig();
  AttentionNetworkConfig two_config = one_config;
  two_config.goal_tokens = 2;
  Rng rng_one(8), rng_two(8), rng(9);
  PolicyNetwork<double> one("policy", one_config, rng_one);
  PolicyNetwork<double> two("policy", two_config, rng_two);
  QNetwork<double> q_one("q1", one_config, rng_one), q_two("q1", two_config, rng_two);
  RandomizeBiases(one.Parameters(), rng);
  RandomizeBiases(q_one.Parameters(), rng);
  auto copy = [](const ParameterList<double>& from, const ParameterList<double>& to) {
    ASSERT_EQ(from.size(), to.size());
    for (size_t i = 0; i < from.size(); ++i) to[i]->value = from[i]->value;
  };
  copy(one.Parameters(), two.Parameters());
  copy(q_one.Parameters(), q_two.Parameters());
  const int D = one_config.goal_dim;
  std::vector<MatD> sets;
  for (int n : {3, 5}) sets.push_back(nn::RandomNormal<double>(n, 5, rng));
  MatD first = nn::RandomNormal<double>(2, D, rng), second = nn::RandomNormal<double>(2, D, rng);
  first.col(D - 1).setOnes();
  second.col(D - 1).setOnes();
  MatD padded = MatD::Zero(2, 2 * D), pair(2, 2 * D);
  padded.leftCols(D) = first;
  pair << first, second;
  const MatD actions = nn::RandomNormal<double>(2, 2, rng), eps = MatD::Zero(2, 2);
  auto q_of = [&](QNetwork<double>& q, const MatD& goals) {
    Tape<double> t;
    return MatD(q.Forward(t, PackEntities(sets, goals), t.Constant(actions)).value());
  };
  auto action_of = [&](PolicyNetwork<double>& p, const MatD& goals) {
    Tape<double> t;
    return MatD(p.Forward(t, PackEntities(sets, goals), eps).action.value());
  };
  EXPECT_LT((q_of(q_two, padded) - q_of(q_one, first)).norm(), 1e-12);
  EXPECT_LT((action_of(two, padded) - action_of(one, first)).norm(), 1e-12);
  // the pair: differs from either token alone
  EXPECT_GT((q_of(q_two, pair) - q_of(q_one, first)).norm(), 1e-6);
  EXPECT_GT((q_of(q_two, pair) - q_of(q_one, second)).norm(), 1e-6);
  EXPECT_LT(nn::testing::GradCheck(
                q_two.Parameters(),
                [&](Tape<double>& t) { return q_two.Forward(t, PackEntities(sets, pair), t.Constant(actions)); }),
            kTol);
  // the actors' fast path agrees with the tape, for a pair and for a padded pair
  for (const MatD& goals : {pair, padded}) {
    Tape<double> t;
    auto mode = two.Forward(t, PackEntities<double>({sets[1]}, goals.row(1)), MatD::Zero(1, 2));
    Rng act_rng(5);
    EXPECT_LT((two.Act(sets[1], goals.row(1), true, act_rng) - mode.action.value()).norm(), 1e-12);
    EXPECT_NEAR(two.last_log_prob(), mode.log_prob.value()(0, 0), 1e-9);
  }
}

TEST(NetworksConfigTest, PaperSizesAndSignature) {
  Rng rng(1);
  PolicyNetwork<float> policy("policy", PaperNetworkConfig(4), rng);
  QNetwork<float> q("q1", PaperNetworkConfig(4), rng);
  const std::string sig = nn::SignatureString(policy.Parameters());
  EXPECT_NE(sig.find("policy.attention.goal.w:7x80;"), std::string::npos) << sig;
  EXPECT_EQ(sig.find("policy.attention.goal.b"), std::string::npos) << "goal linear has no bias";
  EXPECT_NE(sig.find("policy.mlp.0.w:160x128;"), std::string::npos) << sig;
  EXPECT_NE(sig.find("policy.mlp.2.w:128x4;"), std::string::npos) << sig;
  const std::string qsig = nn::SignatureString(q.Parameters());
  EXPECT_NE(qsig.find("q1.mlp.0.w:162x128;"), std::string::npos) << qsig;
  EXPECT_NE(qsig.find("q1.mlp.3.w:128x1;"), std::string::npos) << qsig;
  // the networks accept any number of entities: 7 entities with the same weights
  const nn::Tensor ents = nn::Tensor::Random(7, 6);
  const nn::Tensor goal = nn::Tensor::Random(1, 7);
  const nn::Tensor a = policy.Act(ents, goal, true, rng);
  EXPECT_TRUE(a.allFinite());
  EXPECT_LT(a.cwiseAbs().maxCoeff(), 1.f);
}

TEST(NetworksConfigTest, ValidationNamesTheField) {
  AttentionNetworkConfig c = PaperNetworkConfig(4);
  c.num_heads = 3;
  try {
    c.Validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("num_heads"), std::string::npos);
  }
  c = PaperNetworkConfig(4);
  c.embed_dim = 0;
  Rng rng(1);
  EXPECT_THROW(PolicyNetwork<float>("p", c, rng), std::invalid_argument);
}

TEST(NetworksTrainingTest, PolicyLearnsToPointAtTheGoal) {
  // a sanity check that gradients flow end to end: the deterministic action learns to match
  // the goal's xy (a function of the goal token only)
  AttentionNetworkConfig c = SmallNetworkConfig();
  c.entity_dim = 4;
  c.goal_dim = 5;
  Rng rng(3);
  PolicyNetwork<float> policy("policy", c, rng);
  auto params = policy.Parameters();
  nn::Adam<float> adam(params, {.lr = 3e-3});
  nn::Tape<float> t;
  const int batch = 64;
  float loss_value = 0;
  for (int step = 0; step < 600; ++step) {
    std::vector<nn::Tensor> sets;
    for (int b = 0; b < batch; ++b) sets.push_back(nn::Tensor::Random(3, 4));
    nn::Tensor goals = nn::Tensor::Random(batch, 5) * 0.8f;
    const auto data = PackEntities(sets, goals);
    t.Reset();
    auto out = policy.Forward(t, data, nn::Tensor::Zero(batch, 2));
    auto loss = t.Mean(t.Square(t.Sub(out.action, t.Constant(goals.leftCols(2)))));
    nn::ZeroGrad(params);
    t.Backward(loss);
    adam.Step();
    loss_value = loss.value()(0, 0);
  }
  EXPECT_LT(loss_value, 0.01f);
}

// Issue 34 (reference-deviations row 9): the reference's starting values. The same rng gives the
// same weights; only biases differ: hidden layers 0.1, the policy's log-std outputs log(0.2), so
// the policy starts with a std near 0.2 where Xavier with zero biases gives about 1.
TEST(NetworksConfigTest, ReferenceInitialisationSetsBiasesOnlyAndStartsThePolicyNearStd02) {
  AttentionNetworkConfig plain_config = PaperNetworkConfig(5);
  AttentionNetworkConfig ref_config = plain_config;
  ref_config.initial_policy_std = 0.2;
  ref_config.hidden_bias = 0.1;
  Rng a(3), b(3);
  PolicyNetwork<double> plain("policy", plain_config, a), ref("policy", ref_config, b);
  QNetwork<double> plain_q("q1", plain_config, a), ref_q("q1", ref_config, b);
  for (auto [x, y] :
       {std::pair{plain.Parameters(), ref.Parameters()}, std::pair{plain_q.Parameters(), ref_q.Parameters()}}) {
    ASSERT_EQ(x.size(), y.size());
    for (size_t i = 0; i < x.size(); ++i) {
      const std::string& name = x[i]->name;
      const bool hidden_bias = name.find(".mlp.") != std::string::npos && name.back() == 'b' &&
                               name != "policy.mlp.2.b" && name != "q1.mlp.3.b";
      if (name == "policy.mlp.2.b") {  // [mean | log std] over 2 actions
        EXPECT_EQ(y[i]->value.leftCols(2), x[i]->value.leftCols(2));
        EXPECT_DOUBLE_EQ(y[i]->value(0, 2), std::log(0.2));
        EXPECT_DOUBLE_EQ(y[i]->value(0, 3), std::log(0.2));
      } else if (hidden_bias) {
        EXPECT_TRUE(x[i]->value.isZero()) << name;
        EXPECT_TRUE((y[i]->value.array() == 0.1).all()) << name;
      } else {
        EXPECT_EQ(x[i]->value, y[i]->value) << name << " changed";
      }
    }
  }
  // the std at the start, over 256 observations of a 5-entity table: tanh(mean + std) against
  // tanh(mean) gives each action's std; their geometric mean
  Rng data(9);
  std::vector<MatD> sets;
  for (int k = 0; k < 256; ++k) {
    MatD e = MatD::Zero(5, 7);
    for (int n = 0; n < 5; ++n) e(n, n) = 1, e(n, 5) = 0.2 * nn::RandomNormal<double>(1, 1, data)(0, 0), e(n, 6) = 0.55;
    sets.push_back(e);
  }
  MatD goals = MatD::Zero(256, 8);
  for (int k = 0; k < 256; ++k) goals(k, k % 5) = 1, goals(k, 5) = 0.1, goals(k, 6) = 0.6, goals(k, 7) = 1;
  const auto batch = PackEntities(sets, goals);
  auto mean_log_std = [&](PolicyNetwork<double>& policy) {
    Tape<double> t;
    const MatD mode = policy.Forward(t, batch, MatD::Zero(256, 2)).action.value();
    t.Reset();
    const MatD shifted = policy.Forward(t, batch, MatD::Ones(256, 2)).action.value();
    return ((shifted.array().atanh() - mode.array().atanh()).log()).mean();
  };
  EXPECT_NEAR(std::exp(mean_log_std(ref)), 0.2, 0.1);
  EXPECT_GT(std::exp(mean_log_std(plain)), 0.5);
}

}  // namespace
}  // namespace srics::rl
