#include "common/nn/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "common/nn/modules.h"
#include "common/nn/tape.h"

namespace srics::nn {
namespace {

TEST(WorkerPoolTest, RunsEveryPartOnceOnItsOwnThreadAndReturnsWhenAllAreDone) {
  WorkerPool pool(3);
  ASSERT_EQ(pool.size(), 3);
  for (int round = 0; round < 100; ++round) {
    std::vector<int> ran(3, 0);
    std::vector<std::thread::id> ids(3);
    pool.Run([&](int part) {
      ran[part] += 1;
      ids[part] = std::this_thread::get_id();
    });
    EXPECT_EQ(ran, std::vector<int>({1, 1, 1}));
    EXPECT_EQ(ids[0], std::this_thread::get_id());  // part 0 on the caller
    EXPECT_NE(ids[1], ids[0]);
    EXPECT_NE(ids[2], ids[1]);
  }
}

TEST(WorkerPoolTest, OneThreadRunsInline) {
  WorkerPool pool(1);
  int calls = 0;
  pool.Run([&](int part) {
    EXPECT_EQ(part, 0);
    ++calls;
  });
  EXPECT_EQ(calls, 1);
  EXPECT_THROW(WorkerPool(0), std::invalid_argument);
}

TEST(WorkerPoolTest, AnExceptionOfAWorkerReachesTheCallerAndThePoolStaysUsable) {
  WorkerPool pool(2);
  EXPECT_THROW(pool.Run([](int part) {
    if (part == 1) throw std::runtime_error("part 1 failed");
  }),
               std::runtime_error);
  std::atomic<int> done{0};
  pool.Run([&](int) { ++done; });
  EXPECT_EQ(done.load(), 2);
}

TEST(PartRowsTest, SplitsIntoContiguousNearEqualParts) {
  EXPECT_EQ(PartRows(64, 3, 0), std::make_pair(0, 21));
  EXPECT_EQ(PartRows(64, 3, 1), std::make_pair(21, 42));
  EXPECT_EQ(PartRows(64, 3, 2), std::make_pair(42, 64));
  EXPECT_EQ(PartRows(10, 1, 0), std::make_pair(0, 10));
}

TEST(GradientBufferTest, ShardsOnTwoThreadsGiveTheWholeBatchGradient) {
  // loss = mean over 40 rows of MLP(x)^2: two tapes on two threads, one per half, each with
  // its half's share of the mean; tape 1 writes into a buffer that is added afterwards
  Rng rng(3);
  Mlp<double> mlp("m", 5, {7}, 2, rng, Activation::kTanh);
  ParameterList<double> params;
  mlp.Parameters(params);
  const Matrix<double> x = Matrix<double>::Random(40, 5);

  Tape<double> whole;
  ZeroGrad(params);
  whole.Backward(whole.Mean(whole.Square(mlp.Forward(whole, whole.Constant(x)))));
  std::vector<Matrix<double>> expected;
  for (auto* p : params) expected.push_back(p->grad);

  Tape<double> tapes[2];
  GradientBuffer<double> buffer(params);
  tapes[1].set_gradient_buffer(&buffer);
  WorkerPool pool(2);
  ZeroGrad(params);
  pool.Run([&](int part) {
    const auto [begin, end] = PartRows(40, 2, part);
    Tape<double>& t = tapes[part];
    auto loss = t.Mean(t.Square(mlp.Forward(t, t.Constant(x.middleRows(begin, end - begin)))));
    t.Backward(t.MulScalar(loss, (end - begin) / 40.0));
  });
  // before the reduce, Parameter::grad holds the first half's gradient only
  EXPECT_GT((params[0]->grad - expected[0]).norm(), 1e-6);
  buffer.AddInto();
  for (size_t i = 0; i < params.size(); ++i)
    EXPECT_LT((params[i]->grad - expected[i]).norm(), 1e-12 * (1 + expected[i].norm())) << params[i]->name;
  // AddInto empties the buffer: a second reduce adds nothing
  buffer.AddInto();
  for (size_t i = 0; i < params.size(); ++i)
    EXPECT_LT((params[i]->grad - expected[i]).norm(), 1e-12 * (1 + expected[i].norm()));
}

TEST(GradientBufferTest, AParameterOutsideTheListIsRefused) {
  Parameter<float> a("a", 1, 1), b("b", 1, 1);
  GradientBuffer<float> buffer({&a});
  EXPECT_THROW(buffer.Add(&b, Matrix<float>::Ones(1, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace srics::nn
