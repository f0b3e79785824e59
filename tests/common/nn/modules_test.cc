// Modules against finite differences (double), plus behaviour: attention invariances, the
// tanh-Gaussian density, the inference paths matching the tape.
#include "common/nn/modules.h"

#include <gtest/gtest.h>

#include <numeric>

#include "tests/common/nn/gradcheck.h"

namespace srics::nn {
namespace {

using testing::D;
using testing::GradCheck;
using testing::MatD;

constexpr double kTol = 1e-6;

ParameterList<D> WithInputs(ParameterList<D> params, std::initializer_list<Parameter<D>*> in) {
  params.insert(params.end(), in.begin(), in.end());
  return params;
}

Parameter<D> Input(const std::string& name, Eigen::Index rows, Eigen::Index cols, Rng& rng) {
  Parameter<D> p(name, rows, cols);
  p.value = RandomNormal<D>(rows, cols, rng);
  return p;
}

// A module's tape-free Apply gives what its Forward gives on the input x.
template <typename Module>
void ExpectApplyMatchesForward(Module& module, Parameter<D>& x) {
  MatD y;
  module.Apply(x.value, y);
  Tape<D> t;
  EXPECT_LT((y - module.Forward(t, t.Param(x)).value()).norm(), 1e-12);
}

TEST(ModulesTest, LinearXavierRangeAndGradient) {
  Rng rng(1);
  Linear<D> layer("l", 30, 20, true, rng);
  const double bound = std::sqrt(6.0 / 50.0);
  EXPECT_LE(layer.weight().value.cwiseAbs().maxCoeff(), bound);
  EXPECT_GT(layer.weight().value.cwiseAbs().maxCoeff(), 0.8 * bound);
  EXPECT_EQ(layer.bias()->value.norm(), 0.0);
  layer.bias()->value = RandomNormal<D>(1, 20, rng);
  Parameter<D> x = Input("x", 4, 30, rng);
  ParameterList<D> params;
  layer.Parameters(params);
  EXPECT_LT(GradCheck(WithInputs(params, {&x}), [&](Tape<D>& t) { return layer.Forward(t, t.Param(x)); }), kTol);
  ExpectApplyMatchesForward(layer, x);
}

TEST(ModulesTest, MlpGradientAndApply) {
  Rng rng(2);
  Mlp<D> mlp("m", 5, {7, 6}, 3, rng, Activation::kTanh, Activation::kNone);
  Parameter<D> x = Input("x", 4, 5, rng);
  ParameterList<D> params;
  mlp.Parameters(params);
  EXPECT_EQ(params.size(), 6u);
  EXPECT_LT(GradCheck(WithInputs(params, {&x}), [&](Tape<D>& t) { return mlp.Forward(t, t.Param(x)); }), kTol);
  Mlp<D> relu("r", 5, {8}, 2, rng);
  ParameterList<D> rp;
  relu.Parameters(rp);
  ExpectApplyMatchesForward(relu, x);
}

TEST(ModulesTest, GruUnrolledFiveSteps) {
  Rng rng(3);
  GruCell<D> gru("g", 3, 4, rng);
  ParameterList<D> params;
  gru.Parameters(params);
  for (Parameter<D>* p : params) {
    if (p->value.rows() == 1) p->value = RandomNormal<D>(1, p->value.cols(), rng) * 0.3;
  }
  std::vector<Parameter<D>> xs;
  for (int s = 0; s < 5; ++s) xs.push_back(Input("x" + std::to_string(s), 2, 3, rng));
  Parameter<D> h0 = Input("h0", 2, 4, rng);
  ParameterList<D> vars = WithInputs(params, {&h0});
  for (auto& x : xs) vars.push_back(&x);
  auto unroll = [&](Tape<D>& t) {
    Var<D> h = t.Param(h0);
    for (auto& x : xs) h = gru.Forward(t, t.Param(x), h);
    return h;
  };
  EXPECT_LT(GradCheck(vars, unroll), kTol);
  // one step by hand (PyTorch gate convention)
  Tape<D> t;
  const MatD h1 = gru.Forward(t, t.Param(xs[0]), t.Param(h0)).value();
  const MatD gi = xs[0].value * params[0]->value + params[1]->value.replicate(2, 1);
  const MatD gh = h0.value * params[2]->value + params[3]->value.replicate(2, 1);
  auto sig = [](const MatD& m) { return (1.0 / (1.0 + (-m.array()).exp())).matrix().eval(); };
  const MatD r = sig(gi.leftCols(4) + gh.leftCols(4));
  const MatD z = sig(gi.middleCols(4, 4) + gh.middleCols(4, 4));
  const MatD n = (gi.rightCols(4) + r.cwiseProduct(gh.rightCols(4))).array().tanh().matrix();
  const MatD expect = ((1.0 - z.array()) * n.array() + z.array() * h0.value.array()).matrix();
  EXPECT_LT((h1 - expect).norm(), 1e-12);
}

class AttentionTest : public ::testing::Test {
 protected:
  AttentionTest() : att_("a", {5, 6, 8, 2}, rng_) {
    att_.Parameters(params_);
    for (Parameter<D>* p : params_) {
      if (p->value.rows() == 1) p->value = RandomNormal<D>(1, p->value.cols(), rng_) * 0.3;
    }
  }
  Rng rng_{4};
  GoalAttention<D> att_;
  ParameterList<D> params_;
};

TEST_F(AttentionTest, GradientWithPaddingMask) {
  const int batch = 3, ents = 4;
  Parameter<D> e = Input("e", batch * ents, 5, rng_);
  Parameter<D> g = Input("g", batch, 6, rng_);
  MatD mask = MatD::Ones(batch, ents);
  mask(0, 3) = mask(2, 1) = mask(2, 2) = 0;
  EXPECT_LT(GradCheck(WithInputs(params_, {&e, &g}),
                      [&](Tape<D>& t) {
                        auto out = att_.Forward(t, t.Param(e), t.Constant(mask), t.Param(g));
                        return t.Concat({out.attention, out.goal_embedding}, 1);
                      }),
            // 1.4e-6 on an AVX2-only EPYC (below 1e-6 with AVX-512): the central difference
            // meets a relu kink of this draw; a wrong backward formula gives ~1e-1
            10 * kTol);
}

TEST_F(AttentionTest, PermutationInvariantAndPaddingIgnored) {
  const int ents = 5;
  const MatD set = RandomNormal<D>(ents, 5, rng_);
  const MatD goal = RandomNormal<D>(1, 6, rng_);
  Tape<D> t;
  auto run = [&](const MatD& entities, const MatD& mask) {
    t.Reset();
    return MatD(att_.Forward(t, t.Constant(entities), t.Constant(mask), t.Constant(goal)).attention.value());
  };
  const MatD base = run(set, MatD::Ones(1, ents));
  std::vector<int> perm = {3, 0, 4, 1, 2};
  MatD shuffled(ents, 5);
  for (int i = 0; i < ents; ++i) shuffled.row(i) = set.row(perm[i]);
  EXPECT_LT((run(shuffled, MatD::Ones(1, ents)) - base).norm(), 1e-12);
  // two padding rows of garbage, masked out, change nothing
  MatD padded(ents + 2, 5);
  padded << set, MatD::Constant(2, 5, 1e3);
  MatD mask = MatD::Ones(1, ents + 2);
  mask(0, ents) = mask(0, ents + 1) = 0;
  EXPECT_LT((run(padded, mask) - base).norm(), 1e-12);
  // and the single-sample inference path agrees
  MatD a, ge;
  att_.Apply(set, goal, a, ge);
  EXPECT_LT((a - base).norm(), 1e-12);
}

// Two goal tokens per sample: the attention output and the goal embedding are the sums of what
// each real token gives alone (same parameters), a padding token adds nothing, and the
// parameters' gradients match differences.
TEST(GoalTokensTest, TwoTokensAreTheSumOfEachAloneAndPaddingAddsNothing) {
  Rng rng_one(4), rng_two(4), rng(5);
  GoalAttention<D> one("a", {5, 6, 8, 2}, rng_one);
  GoalAttention<D> two("a", {5, 6, 8, 2, 2}, rng_two);
  ParameterList<D> p_one, p_two;
  one.Parameters(p_one);
  two.Parameters(p_two);
  for (size_t i = 0; i < p_one.size(); ++i) {
    if (p_one[i]->value.rows() == 1) p_one[i]->value = RandomNormal<D>(1, p_one[i]->value.cols(), rng) * 0.3;
    p_two[i]->value = p_one[i]->value;
  }
  const int batch = 3, ents = 4;
  const MatD entities = RandomNormal<D>(batch * ents, 5, rng);
  MatD mask = MatD::Ones(batch, ents);
  mask(1, 2) = 0;
  MatD first = RandomNormal<D>(batch, 6, rng), second = RandomNormal<D>(batch, 6, rng);
  first.col(5).setOnes();
  second.col(5).setOnes();
  second.row(2).setZero();  // sample 2: one real token and a padding one
  MatD goals(batch, 12);
  goals << first, second;
  auto run = [&](GoalAttention<D>& att, const MatD& g) {
    Tape<D> t;
    auto out = att.Forward(t, t.Constant(entities), t.Constant(mask), t.Constant(g));
    return std::make_pair(MatD(out.attention.value()), MatD(out.goal_embedding.value()));
  };
  const auto [pair_att, pair_ge] = run(two, goals);
  const auto [first_att, first_ge] = run(one, first);
  const auto [second_att, second_ge] = run(one, second);
  for (int b = 0; b < batch; ++b) {
    const double second_share = b == 2 ? 0.0 : 1.0;
    EXPECT_LT((pair_att.row(b) - first_att.row(b) - second_share * second_att.row(b)).norm(), 1e-12) << b;
    EXPECT_LT((pair_ge.row(b) - first_ge.row(b) - second_share * second_ge.row(b)).norm(), 1e-12) << b;
    // the actors' path: the same sums for one sample
    MatD a, ge;
    two.Apply(entities.middleRows(b * ents, ents), goals.row(b), a, ge);
    if (b != 1) {  // sample 1 has a masked entity, which Apply (all present) does not
      EXPECT_LT((a - pair_att.row(b)).norm(), 1e-12) << b;
      EXPECT_LT((ge - pair_ge.row(b)).norm(), 1e-12) << b;
    }
  }
  // (the parameters' gradients: a token's constant-1 feature is its mask, so the goals are
  // constants, as every caller passes them)
  EXPECT_LT(GradCheck(p_two,
                      [&](Tape<D>& t) {
                        auto out = two.Forward(t, t.Constant(entities), t.Constant(mask), t.Constant(goals));
                        return t.Concat({out.attention, out.goal_embedding}, 1);
                      }),
            10 * kTol);
  EXPECT_THROW(GoalAttention<D>("a", {5, 6, 8, 2, 0}, rng), std::invalid_argument);
}

TEST(ComposingTest, PaysOnTrainingBatchesNotOnOneSample) {
  // Rearrange's entity tokens (6 features -> 80 -> key and value) over batch 2048 x 4:
  // layered 8192 * 480 + 2 * 8192 * 6400 = 108.8M multiply-adds, composed
  // 2 * (8192 * 480 + 6 * 6400 + 6400) = 7.95M
  EXPECT_TRUE(ComposingPays(8192, 6, 80, 80, 2, false));
  // one sample of 5 entities: 66.4k layered against 94.4k composed
  EXPECT_FALSE(ComposingPays(5, 6, 80, 80, 2, false));
  // the goal's query when its embedding is needed anyway: 2048 * 6400 = 13.1M against
  // 2048 * 560 + 7 * 6400 + 6400 = 1.2M; with a single goal, 6400 against 52.4k
  EXPECT_TRUE(ComposingPays(2048, 7, 80, 80, 1, true));
  EXPECT_FALSE(ComposingPays(1, 7, 80, 80, 1, true));
}

// On a batch large enough that keys, values and queries run as composed products, the
// network is the same function (each sample as the layer-by-layer inference path computes
// it) and its gradients match finite differences.
TEST(ComposingTest, ComposedAttentionIsTheLayeredFunctionWithItsGradient) {
  Rng rng(6);
  const AttentionConfig config{5, 6, 16, 2};
  GoalAttention<D> att("a", config, rng);
  ParameterList<D> params;
  att.Parameters(params);
  for (Parameter<D>* p : params) {
    if (p->value.rows() == 1) p->value = RandomNormal<D>(1, p->value.cols(), rng) * 0.3;
  }
  const int batch = 16, ents = 4;
  ASSERT_TRUE(ComposingPays(batch * ents, 5, 16, 16, 2, false));
  ASSERT_TRUE(ComposingPays(batch, 6, 16, 16, 1, true));
  Parameter<D> e = Input("e", batch * ents, 5, rng);
  Parameter<D> g = Input("g", batch, 6, rng);
  const MatD mask = MatD::Ones(batch, ents);
  Tape<D> t;
  auto out = att.Forward(t, t.Constant(e.value), t.Constant(mask), t.Constant(g.value));
  for (int b = 0; b < batch; ++b) {
    MatD a, ge;
    att.Apply(e.value.middleRows(b * ents, ents), g.value.row(b), a, ge);
    EXPECT_LT((a - out.attention.value().row(b)).norm(), 1e-12) << "sample " << b;
    EXPECT_LT((ge - out.goal_embedding.value().row(b)).norm(), 1e-12) << "sample " << b;
  }
  EXPECT_LT(GradCheck(
                WithInputs(params, {&e, &g}),
                [&](Tape<D>& tape) {
                  auto o = att.Forward(tape, tape.Param(e), tape.Constant(mask), tape.Param(g));
                  return tape.Concat({o.attention, o.goal_embedding}, 1);
                },
                /*h=*/1e-5),  // with 16 samples, 1e-6 steps leave ~2e-6 of differencing noise
            kTol);            // on the key bias's zero gradient; a wrong formula gives ~1e-1
}

TEST(TanhGaussianTest, LogProbGradientAndDensity) {
  Rng rng(5);
  TanhGaussian<D> head;
  Parameter<D> out = Input("out", 4, 4, rng);  // [mean | log std] for 2 actions
  const MatD eps = RandomNormal<D>(4, 2, rng);
  EXPECT_LT(GradCheck({&out},
                      [&](Tape<D>& t) {
                        auto s = head.Forward(t, t.Param(out), eps);
                        return t.Concat({s.action, s.log_prob}, 1);
                      }),
            kTol);
  // density of a = tanh(u), u ~ N(mean, std): log N(u) - sum log(1 - a^2), computed directly
  Tape<D> t;
  auto s = head.Forward(t, t.Param(out), eps);
  for (int b = 0; b < 4; ++b) {
    double expect = 0;
    for (int i = 0; i < 2; ++i) {
      const double ls = std::clamp(out.value(b, 2 + i), -20.0, 2.0);
      const double u = out.value(b, i) + std::exp(ls) * eps(b, i);
      expect +=
          -0.5 * eps(b, i) * eps(b, i) - ls - 0.5 * std::log(2 * M_PI) - std::log(1 - std::tanh(u) * std::tanh(u));
      EXPECT_NEAR(s.action.value()(b, i), std::tanh(u), 1e-12);
    }
    EXPECT_NEAR(s.log_prob.value()(b, 0), expect, 1e-9);
    double action[2];
    EXPECT_NEAR(head.Apply(out.value.row(b).data(), 2, eps.row(b).data(), action), expect, 1e-9);
  }
}

TEST(TanhGaussianTest, LogStdIsClampedAndModeIsTanhMean) {
  TanhGaussian<D> head;
  MatD out(1, 4);
  out << 0.3, -0.2, 5.0, -30.0;  // log std above 2 and below -20
  Tape<D> t;
  auto s = head.Forward(t, t.Constant(out, true), MatD::Zero(1, 2));
  EXPECT_NEAR(s.action.value()(0, 0), std::tanh(0.3), 1e-15);
  EXPECT_NEAR(s.action.value()(0, 1), std::tanh(-0.2), 1e-15);
  const double expect = -std::log(2 * M_PI) - 2.0 + 20.0 - std::log(1 - std::pow(std::tanh(0.3), 2)) -
                        std::log(1 - std::pow(std::tanh(-0.2), 2));
  EXPECT_NEAR(s.log_prob.value()(0, 0), expect, 1e-9);
  // outside the clip range the log std gets no gradient
  Var<D> in{&t, 0};
  t.Backward(t.Sum(s.log_prob));
  EXPECT_EQ(in.grad()(0, 2), 0.0);
  EXPECT_EQ(in.grad()(0, 3), 0.0);
}

TEST(TanhGaussianTest, ExtremeMeansStayFinite) {
  TanhGaussian<float> head;
  Tensor out(1, 4);
  out << 40.f, -40.f, 0.f, 0.f;
  Tape<float> t;
  auto s = head.Forward(t, t.Constant(out), Tensor::Zero(1, 2));
  EXPECT_TRUE(std::isfinite(s.log_prob.value()(0, 0)));
}

}  // namespace
}  // namespace srics::nn
