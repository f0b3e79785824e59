// Optimizers against hand-computed steps, gradient clipping, and learning a regression.
#include "common/nn/optim.h"

#include <limits>

#include <gtest/gtest.h>

#include "common/nn/modules.h"

namespace srics::nn {
namespace {

TEST(AdamTest, MatchesHandComputedSteps) {
  Parameter<double> p("p", 1, 2);
  p.value << 1.0, -2.0;
  Adam<double> adam({&p}, {.lr = 0.1, .beta1 = 0.9, .beta2 = 0.999, .eps = 1e-8});
  // step 1, g = (0.5, -1): m = 0.1 g, v = 0.001 g^2, m_hat = g, v_hat = g^2 -> p -= 0.1 sign(g)
  p.grad << 0.5, -1.0;
  adam.Step();
  EXPECT_NEAR(p.value(0, 0), 1.0 - 0.1 * 0.5 / (0.5 + 1e-8), 1e-12);
  EXPECT_NEAR(p.value(0, 1), -2.0 + 0.1 * 1.0 / (1.0 + 1e-8), 1e-12);
  // step 2, g = (0.25, 2)
  p.grad << 0.25, 2.0;
  const double x0 = p.value(0, 0), x1 = p.value(0, 1);
  adam.Step();
  auto expect = [](double x, double g1, double g2) {
    const double m = 0.9 * (0.1 * g1) + 0.1 * g2;
    const double v = 0.999 * (0.001 * g1 * g1) + 0.001 * g2 * g2;
    const double m_hat = m / (1 - 0.81), v_hat = v / (1 - 0.999 * 0.999);
    return x - 0.1 * m_hat / (std::sqrt(v_hat) + 1e-8);
  };
  EXPECT_NEAR(p.value(0, 0), expect(x0, 0.5, 0.25), 1e-12);
  EXPECT_NEAR(p.value(0, 1), expect(x1, -1.0, 2.0), 1e-12);
  EXPECT_EQ(adam.steps(), 2);
}

TEST(AdamTest, StateIsPerParameterAndRoundTrips) {
  Parameter<float> a("a", 2, 2), b("b", 1, 3);
  a.grad.setConstant(1.f);
  b.grad.setConstant(-3.f);
  Adam<float> adam({&a, &b}, {});
  adam.Step();
  adam.Step();
  const auto state = adam.ExportState();
  EXPECT_EQ(state.size(), 2u + 2 * 7);
  Parameter<float> a2("a", 2, 2), b2("b", 1, 3);
  a2.value = a.value;
  b2.value = b.value;
  a2.grad = a.grad;
  b2.grad = b.grad;
  Adam<float> restored({&a2, &b2}, {});
  restored.ImportState(state);
  adam.Step();
  restored.Step();
  EXPECT_EQ(a.value, a2.value);
  EXPECT_EQ(b.value, b2.value);
  EXPECT_EQ(restored.steps(), 3);
  EXPECT_THROW(restored.ImportState(std::vector<float>(3)), std::invalid_argument);
}

TEST(RmsPropTest, MatchesHandComputedSteps) {
  Parameter<double> p("p", 1, 1);
  p.value << 1.0;
  RmsProp<double> opt({&p}, {.lr = 0.01, .alpha = 0.99, .eps = 1e-8});
  p.grad << 2.0;
  opt.Step();
  double v = 0.01 * 4.0;
  double x = 1.0 - 0.01 * 2.0 / (std::sqrt(v) + 1e-8);
  EXPECT_NEAR(p.value(0, 0), x, 1e-12);
  p.grad << -1.0;
  opt.Step();
  v = 0.99 * v + 0.01 * 1.0;
  x = x + 0.01 * 1.0 / (std::sqrt(v) + 1e-8);
  EXPECT_NEAR(p.value(0, 0), x, 1e-12);
}

TEST(ClipGradNormTest, ScalesToMaxNormAndReportsNorm) {
  Parameter<double> a("a", 1, 2), b("b", 1, 1);
  a.grad << 3.0, 0.0;
  b.grad << 4.0;
  EXPECT_NEAR(ClipGradNorm<double>({&a, &b}, 1.0), 5.0, 1e-12);
  EXPECT_NEAR(std::sqrt(a.grad.squaredNorm() + b.grad.squaredNorm()), 1.0, 1e-9);
  EXPECT_NEAR(a.grad(0, 0) / b.grad(0, 0), 0.75, 1e-12);
  EXPECT_NEAR(ClipGradNorm<double>({&a, &b}, 10.0), 1.0, 1e-9);  // below: untouched
  EXPECT_NEAR(a.grad(0, 0), 0.6, 1e-9);
}

TEST(GradientsUsableTest, FiniteGradientsUpToTheBoundOnly) {
  Parameter<float> a("a", 1, 2), b("b", 2, 1);
  EXPECT_TRUE(GradientsUsable<float>({&a, &b}));  // zeros
  a.grad << 1e17f, -1e18f;                        // the bound itself is usable
  EXPECT_TRUE(GradientsUsable<float>({&a, &b}));
  b.grad << 0.f, -2e18f;  // its square would overflow Adam's float moment
  EXPECT_FALSE(GradientsUsable<float>({&a, &b}));
  b.grad << std::numeric_limits<float>::infinity(), 0.f;
  EXPECT_FALSE(GradientsUsable<float>({&a, &b}));
  b.grad << 0.f, std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(GradientsUsable<float>({&a, &b}));
  EXPECT_FALSE(GradientsUsable<float>({&b}));
  EXPECT_TRUE(GradientsUsable<float>({&a}));
  EXPECT_TRUE(GradientsUsable<float>({}));
  // one bad value anywhere in a gradient of many (the vector loop's body and its remainder)
  Parameter<float> big("big", 37, 29);
  big.grad.setConstant(0.5f);
  EXPECT_TRUE(GradientsUsable<float>({&big}));
  for (Eigen::Index at : {Eigen::Index(0), Eigen::Index(500), big.grad.size() - 1}) {
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::infinity(), 3e18f}) {
      big.grad(at / 29, at % 29) = bad;
      EXPECT_FALSE(GradientsUsable<float>({&a, &big})) << "at " << at << ": " << bad;
      big.grad(at / 29, at % 29) = 0.5f;
    }
  }
  EXPECT_TRUE(GradientsUsable<float>({&a, &big}));
}

TEST(SoftUpdateTest, PolyakAverage) {
  Parameter<float> t("t", 1, 2), s("s", 1, 2);
  t.value << 1.f, 1.f;
  s.value << 3.f, -1.f;
  SoftUpdate<float>({&t}, {&s}, 0.25);
  EXPECT_FLOAT_EQ(t.value(0, 0), 1.5f);
  EXPECT_FLOAT_EQ(t.value(0, 1), 0.5f);
  SoftUpdate<float>({&t}, {&s}, 1.0);
  EXPECT_EQ(t.value, s.value);
}

TEST(TrainingTest, MlpFitsSmallRegression) {
  Rng rng(11);
  const int n = 256;
  const Tensor x = Tensor::Random(n, 2);
  Tensor y(n, 1);
  for (int i = 0; i < n; ++i) y(i, 0) = std::sin(3 * x(i, 0)) * x(i, 1) + 0.5f * x(i, 0);
  Mlp<float> mlp("m", 2, {32, 32}, 1, rng);
  ParameterList<float> params;
  mlp.Parameters(params);
  Adam<float> adam(params, {.lr = 3e-3});
  Tape<float> tape;
  float first = 0, last = 0;
  for (int step = 0; step < 1500; ++step) {
    tape.Reset();
    Var<float> loss = tape.Mean(tape.Square(tape.Sub(mlp.Forward(tape, tape.Constant(x)), tape.Constant(y))));
    ZeroGrad(params);
    tape.Backward(loss);
    adam.Step();
    if (step == 0) first = loss.value()(0, 0);
    last = loss.value()(0, 0);
  }
  EXPECT_GT(first, 0.1f);
  EXPECT_LT(last, 2e-3f);
}

}  // namespace
}  // namespace srics::nn
