// Every tape operation against central finite differences in double precision.
#include "common/nn/tape.h"

#include <gtest/gtest.h>

#include "tests/common/nn/gradcheck.h"

namespace srics::nn {
namespace {

using testing::AwayFromZero;
using testing::D;
using testing::GradCheck;
using testing::MatD;

constexpr double kTol = 1e-6;

class TapeGradTest : public ::testing::Test {
 protected:
  // A variable of the given shape filled away from zero.
  Parameter<D>& NewVar(Eigen::Index rows, Eigen::Index cols, double lo = 0.05, double hi = 1.5,
                       bool signed_values = true) {
    vars_.push_back(std::make_unique<Parameter<D>>("v" + std::to_string(vars_.size()), rows, cols));
    vars_.back()->value = AwayFromZero(rows, cols, rng_, lo, hi, signed_values);
    return *vars_.back();
  }
  ParameterList<D> All() {
    ParameterList<D> list;
    for (auto& v : vars_) list.push_back(v.get());
    return list;
  }
  Rng rng_{7};
  std::vector<std::unique_ptr<Parameter<D>>> vars_;
};

TEST_F(TapeGradTest, MatMulLinearAddBias) {
  auto& a = NewVar(5, 3);
  auto& b = NewVar(3, 4);
  auto& bias = NewVar(1, 4);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.MatMul(t.Param(a), t.Param(b)); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Linear(t.Param(a), t.Param(b), t.Param(bias)); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.AddBias(t.MatMul(t.Param(a), t.Param(b)), t.Param(bias)); }),
            kTol);
}

TEST_F(TapeGradTest, ElementwiseBinarySameShapeAndBroadcast) {
  auto& a = NewVar(4, 3);
  auto& b = NewVar(4, 3, 0.5, 1.5);  // divisor away from zero
  auto& row = NewVar(1, 3, 0.5, 1.5);
  auto& col = NewVar(4, 1, 0.5, 1.5);
  auto& scalar = NewVar(1, 1, 0.5, 1.5);
  using BinOp = Var<D> (Tape<D>::*)(Var<D>, Var<D>);
  const std::vector<std::pair<const char*, BinOp>> ops = {
      {"add", &Tape<D>::Add}, {"sub", &Tape<D>::Sub}, {"mul", &Tape<D>::Mul}, {"div", &Tape<D>::Div}};
  for (const auto& [name, op_entry] : ops) {
    const BinOp op = op_entry;  // a copy: clang 14 cannot capture a structured binding
    for (Parameter<D>* rhs : {&b, &row, &col, &scalar}) {
      SCOPED_TRACE(std::string(name) + " with " + rhs->name);
      EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return (t.*op)(t.Param(a), t.Param(*rhs)); }), kTol);
    }
    // broadcast on the left operand too
    EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return (t.*op)(t.Param(row), t.Param(b)); }), kTol);
  }
}

TEST_F(TapeGradTest, ScalarMinClamp) {
  auto& a = NewVar(4, 3);
  auto& b = NewVar(4, 3);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.AddScalar(t.Param(a), 0.7); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.MulScalar(t.Param(a), -1.3); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Min(t.Param(a), t.Param(b)); }), kTol);
  // clamp bounds chosen away from the values (all |a| >= 0.05)
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Clamp(t.Param(a), -0.02, 0.03); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Clamp(t.Param(a), -0.5, 0.5); }), kTol);
}

TEST_F(TapeGradTest, UnaryFunctions) {
  auto& a = NewVar(4, 3, 0.05, 3.0);
  auto& pos = NewVar(4, 3, 0.2, 3.0, false);
  using UnOp = Var<D> (Tape<D>::*)(Var<D>);
  const std::vector<std::pair<const char*, UnOp>> ops = {
      {"relu", &Tape<D>::Relu}, {"tanh", &Tape<D>::Tanh},         {"sigmoid", &Tape<D>::Sigmoid},
      {"exp", &Tape<D>::Exp},   {"softplus", &Tape<D>::Softplus}, {"square", &Tape<D>::Square}};
  for (const auto& [name, op_entry] : ops) {
    const UnOp op = op_entry;  // a copy: clang 14 cannot capture a structured binding
    SCOPED_TRACE(name);
    EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return (t.*op)(t.Param(a)); }), kTol);
  }
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Log(t.Param(pos)); }), kTol);
}

TEST_F(TapeGradTest, SoftplusIsOverflowSafe) {
  Tape<float> t;
  Tensor x(1, 3);
  x << -200.f, 0.f, 200.f;
  const Tensor y = t.Softplus(t.Constant(x)).value();
  EXPECT_NEAR(y(0, 0), 0.f, 1e-30);
  EXPECT_NEAR(y(0, 1), std::log(2.f), 1e-6);
  EXPECT_NEAR(y(0, 2), 200.f, 1e-3);
}

TEST_F(TapeGradTest, Reductions) {
  auto& a = NewVar(4, 3);
  for (int axis : {-1, 0, 1}) {
    SCOPED_TRACE(axis);
    EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Sum(t.Param(a), axis); }), kTol);
    EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Mean(t.Param(a), axis); }), kTol);
  }
  Tape<D> t;
  EXPECT_NEAR(t.Mean(t.Param(a), 0).value()(0, 1), a.value.col(1).mean(), 1e-12);
}

TEST_F(TapeGradTest, ShapeOps) {
  auto& a = NewVar(4, 3);
  auto& b = NewVar(4, 2);
  auto& c = NewVar(2, 3);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Concat({t.Param(a), t.Param(b), t.Param(a)}, 1); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Concat({t.Param(a), t.Param(c)}, 0); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Slice(t.Param(a), 1, 1, 2); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Slice(t.Param(a), 0, 1, 2); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Reshape(t.Param(a), 2, 6); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Transpose(t.Param(a)); }), kTol);
  // reshape keeps row-major order
  Tape<D> t;
  EXPECT_EQ(t.Reshape(t.Param(a), 12, 1).value()(4, 0), a.value(1, 1));
}

TEST_F(TapeGradTest, SoftmaxFamily) {
  auto& a = NewVar(3, 5);
  MatD mask = MatD::Ones(3, 5);
  mask(0, 1) = mask(0, 4) = mask(2, 0) = 0;
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Softmax(t.Param(a)); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.MaskedSoftmax(t.Param(a), t.Constant(mask)); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.LogSoftmax(t.Param(a)); }), kTol);
  Tape<D> t;
  const MatD y = t.MaskedSoftmax(t.Param(a), t.Constant(mask)).value();
  EXPECT_EQ(y(0, 1), 0.0);
  EXPECT_EQ(y(2, 0), 0.0);
  EXPECT_NEAR(y.row(0).sum(), 1.0, 1e-12);
  const MatD ls = t.LogSoftmax(t.Param(a)).value();
  EXPECT_NEAR(ls.row(1).array().exp().sum(), 1.0, 1e-12);
}

TEST_F(TapeGradTest, GumbelSoftmaxSoftAndStraightThrough) {
  auto& logits = NewVar(6, 2);
  Rng rng(3);
  const MatD noise = RandomGumbel<D>(6, 2, rng);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.GumbelSoftmax(t.Param(logits), noise, 0.5, false); }), kTol);
  // hard: the forward is one-hot at the argmax of the soft sample, the gradient is the soft one
  Tape<D> t;
  const MatD w = RandomNormal<D>(6, 2, rng);
  ZeroGrad(All());
  Var<D> soft = t.GumbelSoftmax(t.Param(logits), noise, 0.5, false);
  t.Backward(t.Sum(t.Mul(soft, t.Constant(w))));
  const MatD soft_grad = logits.grad;
  const MatD soft_value = soft.value();
  t.Reset();
  ZeroGrad(All());
  Var<D> hard = t.GumbelSoftmax(t.Param(logits), noise, 0.5, true);
  t.Backward(t.Sum(t.Mul(hard, t.Constant(w))));
  for (int i = 0; i < 6; ++i) {
    Eigen::Index j;
    soft_value.row(i).maxCoeff(&j);
    EXPECT_EQ(hard.value()(i, j), 1.0);
    EXPECT_EQ(hard.value().row(i).sum(), 1.0);
  }
  EXPECT_LT((logits.grad - soft_grad).norm(), 1e-14);
  EXPECT_GT(soft_grad.norm(), 1e-3);
}

TEST_F(TapeGradTest, GatherScatter) {
  auto& a = NewVar(4, 3);
  const std::vector<int> idx = {2, 0, 2, 3, 1, 2};
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.Gather(t.Param(a), idx); }), kTol);
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.ScatterAdd(t.Param(a), {1, 1, 0, 4}, 5); }), kTol);
  Tape<D> t;
  const MatD s = t.ScatterAdd(t.Param(a), {1, 1, 0, 4}, 5).value();
  EXPECT_NEAR(s(1, 2), a.value(0, 2) + a.value(1, 2), 1e-12);
  EXPECT_EQ(s(3, 0), 0.0);
}

TEST_F(TapeGradTest, WeightedScatterAddMatchesMulThenScatter) {
  auto& a = NewVar(4, 3);
  auto& w = NewVar(4, 1);
  const std::vector<int> idx = {1, 1, 0, 4};
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.ScatterAdd(t.Param(a), idx, 5, t.Param(w)); }), kTol);
  Tape<D> t;
  const MatD fused = t.ScatterAdd(t.Param(a), idx, 5, t.Param(w)).value();
  const MatD composed = t.ScatterAdd(t.Mul(t.Param(a), t.Param(w)), idx, 5).value();
  EXPECT_LT((fused - composed).norm(), 1e-14);
}

TEST_F(TapeGradTest, GatherSumReluMatchesComposition) {
  auto& a = NewVar(3, 4);
  auto& b = NewVar(4, 4);
  const std::vector<int> a_idx = {0, 2, 2, 1, 0};
  const std::vector<int> b_idx = {3, 3, 0, 1, 2};
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.GatherSumRelu(t.Param(a), a_idx, t.Param(b), b_idx); }), kTol);
  Tape<D> t;
  const MatD fused = t.GatherSumRelu(t.Param(a), a_idx, t.Param(b), b_idx).value();
  const MatD composed = t.Relu(t.Add(t.Gather(t.Param(a), a_idx), t.Gather(t.Param(b), b_idx))).value();
  EXPECT_EQ(fused, composed);
  EXPECT_GT((fused.array() == 0).count(), 0);  // the relu cuts some entries
  // a column range, its gradient into those columns only
  EXPECT_LT(GradCheck(All(), [&](Tape<D>& t) { return t.GatherSumRelu(t.Param(a), a_idx, t.Param(b), b_idx, 1, 2); }),
            kTol);
  EXPECT_EQ(t.GatherSumRelu(t.Param(a), a_idx, t.Param(b), b_idx, 1, 2).value(), fused.middleCols(1, 2));
  EXPECT_THROW(t.GatherSumRelu(t.Param(a), a_idx, t.Param(b), b_idx, 3, 2), std::invalid_argument);
}

// Head sizes 3 (read at run time), 8, 16 (the paper's: 80 = 5 x 16) and 32 (compiled in).
class AttentionGradTest : public TapeGradTest, public ::testing::WithParamInterface<int> {};

TEST_P(AttentionGradTest, AttentionMatchesCompositionAndDifferences) {
  const int batch = 3, ents = 4, heads = 2, dh = GetParam(), embed = heads * dh;
  auto& q = NewVar(batch, embed);
  auto& k = NewVar(batch * ents, embed);
  auto& v = NewVar(batch * ents, embed);
  MatD mask = MatD::Ones(batch, ents);
  mask(0, 3) = mask(1, 0) = mask(1, 2) = 0;
  EXPECT_LT(
      GradCheck(All(),
                [&](Tape<D>& t) { return t.Attention(t.Param(q), t.Param(k), t.Param(v), t.Constant(mask), heads); }),
      kTol);
  // the same attention composed from generic ops (gather, reshape, masked softmax, scatter)
  auto composed = [&](Tape<D>& t) {
    std::vector<int> rep, seg;
    for (int b = 0; b < batch; ++b) {
      for (int e = 0; e < ents; ++e) rep.push_back(b);
    }
    Var<D> qr = t.Gather(t.Param(q), rep);  // (B*N) x E
    Var<D> prod = t.Reshape(t.Mul(qr, t.Param(k)), batch * ents * heads, dh);
    Var<D> scores = t.MulScalar(t.Sum(prod, 1), 1.0 / std::sqrt(double(dh)));
    // (B*N*H) x 1 -> per (b, h) rows over n: transpose each sample's N x H block
    std::vector<int> order;
    for (int b = 0; b < batch; ++b) {
      for (int h = 0; h < heads; ++h) {
        for (int e = 0; e < ents; ++e) order.push_back((b * ents + e) * heads + h);
      }
    }
    Var<D> s = t.Reshape(t.Gather(scores, order), batch * heads, ents);
    std::vector<int> mrep;
    for (int b = 0; b < batch; ++b) {
      for (int h = 0; h < heads; ++h) mrep.push_back(b);
    }
    Var<D> m = t.Gather(t.Constant(mask), mrep);
    Var<D> w = t.MaskedSoftmax(s, m);  // (B*H) x N
    // back to (B*N*H) x 1 in entity-major order, expand over the head's dims
    std::vector<int> inverse(order.size());
    for (size_t i = 0; i < order.size(); ++i) inverse[order[i]] = static_cast<int>(i);
    Var<D> wn = t.Gather(t.Reshape(w, batch * heads * ents, 1), inverse);
    std::vector<int> expand;
    for (int r = 0; r < batch * ents * heads; ++r) {
      for (int d = 0; d < dh; ++d) expand.push_back(r);
    }
    Var<D> wexp = t.Reshape(t.Gather(wn, expand), batch * ents, embed);
    for (int b = 0; b < batch; ++b) {
      for (int e = 0; e < ents; ++e) seg.push_back(b);
    }
    return t.ScatterAdd(t.Mul(wexp, t.Param(v)), seg, batch);
  };
  Tape<D> t1, t2;
  const MatD fused = t1.Attention(t1.Param(q), t1.Param(k), t1.Param(v), t1.Constant(mask), heads).value();
  const MatD ref = composed(t2).value();
  EXPECT_LT((fused - ref).norm(), 1e-12);
  EXPECT_LT(GradCheck(All(), composed), kTol);
}

INSTANTIATE_TEST_SUITE_P(HeadSizes, AttentionGradTest, ::testing::Values(3, 8, 16, 32));

// The float kernels (16-value heads have their own vector dot product, common/nn/attention.cc)
// against the double ones on the same numbers: values, and the gradients of q, k and v, within
// float rounding; per head size compiled in and one read at run time.
TEST(AttentionFloatTest, FloatKernelsMatchTheDoubleOnesForEveryHeadSize) {
  for (int dh : {5, 8, 16, 32}) {
    SCOPED_TRACE("head size " + std::to_string(dh));
    const int batch = 7, ents = 6, heads = 5, embed = heads * dh;
    Rng rng(dh);
    const MatD q = RandomNormal<D>(batch, embed, rng), k = RandomNormal<D>(batch * ents, embed, rng),
               v = RandomNormal<D>(batch * ents, embed, rng), seed = RandomNormal<D>(batch, embed, rng);
    MatD mask = MatD::Ones(batch, ents);
    mask(0, 5) = mask(3, 0) = mask(3, 2) = 0;
    Tape<D> td;
    Var<D> qd = td.Constant(q, true), kd = td.Constant(k, true), vd = td.Constant(v, true);
    Var<D> outd = td.Attention(qd, kd, vd, td.Constant(mask), heads);
    td.Backward(outd, seed);
    Tape<float> tf;
    Var<float> qf = tf.Constant(q.cast<float>(), true), kf = tf.Constant(k.cast<float>(), true),
               vf = tf.Constant(v.cast<float>(), true);
    Var<float> outf = tf.Attention(qf, kf, vf, tf.Constant(mask.cast<float>()), heads);
    tf.Backward(outf, seed.cast<float>());
    auto near = [](const MatD& exact, const Tensor& got) {
      return (exact - got.cast<D>()).cwiseAbs().maxCoeff() / (1.0 + exact.cwiseAbs().maxCoeff());
    };
    EXPECT_LT(near(outd.value(), outf.value()), 1e-5);
    EXPECT_LT(near(qd.grad(), qf.grad()), 1e-5);
    EXPECT_LT(near(kd.grad(), kf.grad()), 1e-5);
    EXPECT_LT(near(vd.grad(), vf.grad()), 1e-5);
    EXPECT_EQ(outf.value().row(3).norm() > 0, true);
  }
}

TEST_F(TapeGradTest, SeveralQueriesPerSampleAttendToTheirOwnSamplesEntities) {
  // 2 queries per sample (a tied pair's two goal tokens): query row b*2 + j sees sample b's
  // entities and mask only, as a one-query attention of that sample would
  const int batch = 3, ents = 4, heads = 2, dh = 3, embed = heads * dh, per_sample = 2;
  auto& q = NewVar(batch * per_sample, embed);
  auto& k = NewVar(batch * ents, embed);
  auto& v = NewVar(batch * ents, embed);
  MatD mask = MatD::Ones(batch, ents);
  mask(0, 3) = mask(1, 0) = mask(2, 1) = 0;
  Tape<D> t;
  const MatD both = t.Attention(t.Param(q), t.Param(k), t.Param(v), t.Constant(mask), heads, per_sample).value();
  ASSERT_EQ(both.rows(), batch * per_sample);
  for (int j = 0; j < per_sample; ++j) {
    MatD qj(batch, embed);
    for (int b = 0; b < batch; ++b) qj.row(b) = q.value.row(b * per_sample + j);
    Tape<D> one;
    const MatD single = one.Attention(one.Constant(qj), one.Param(k), one.Param(v), one.Constant(mask), heads).value();
    for (int b = 0; b < batch; ++b) EXPECT_EQ(both.row(b * per_sample + j), single.row(b)) << "sample " << b;
  }
  // the keys' and values' gradients gather both queries' shares
  EXPECT_LT(GradCheck(All(),
                      [&](Tape<D>& t) {
                        return t.Attention(t.Param(q), t.Param(k), t.Param(v), t.Constant(mask), heads, per_sample);
                      }),
            kTol);
  EXPECT_THROW(t.Attention(t.Param(q), t.Param(k), t.Param(v), t.Constant(mask), heads, 4), std::invalid_argument);
}

TEST_F(TapeGradTest, WrongGradientIsDetected) {
  // sanity of the checker itself: a loss whose true gradient is twice what the tape sees
  auto& a = NewVar(3, 3);
  Parameter<D> frozen("frozen", 3, 3);
  frozen.value = a.value;
  const double err = GradCheck({&a}, [&](Tape<D>& t) {
    frozen.value = a.value;  // a enters twice, but the tape only sees one path
    return t.Mul(t.Param(a), t.Param(frozen, false));
  });
  EXPECT_GT(err, 0.1);
}

TEST(TapeTest, ReuseAfterResetGivesSameResultAndFrozenParamsGetNoGrad) {
  Rng rng(1);
  Parameter<float> w("w", 3, 2);
  w.value = RandomNormal<float>(3, 2, rng);
  const Tensor x = RandomNormal<float>(4, 3, rng);
  Tape<float> t;
  t.Backward(t.Sum(t.MatMul(t.Constant(x), t.Param(w))));
  const Tensor g1 = w.grad;
  t.Reset();
  w.grad.setZero();
  t.Backward(t.Sum(t.MatMul(t.Constant(x), t.Param(w))));
  EXPECT_EQ(g1, w.grad);
  w.grad.setZero();
  t.Reset();
  Var<float> in = t.Constant(x, true);
  t.Backward(t.Sum(t.MatMul(in, t.Param(w, false))));
  EXPECT_EQ(w.grad.norm(), 0.f);
  EXPECT_GT(in.grad().norm(), 0.f);
}

TEST(TapeTest, ShapeErrorsThrow) {
  Tape<float> t;
  EXPECT_THROW(t.MatMul(t.Constant(Tensor::Zero(2, 3)), t.Constant(Tensor::Zero(2, 3))), std::invalid_argument);
  EXPECT_THROW(t.Add(t.Constant(Tensor::Zero(2, 3)), t.Constant(Tensor::Zero(3, 2))), std::invalid_argument);
  EXPECT_THROW(t.Backward(t.Constant(Tensor::Zero(2, 2))), std::invalid_argument);
}

}  // namespace
}  // namespace srics::nn
