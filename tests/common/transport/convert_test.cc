// The conversions between the domain types and the generated C types (common/transport/
// convert.h), no DDS: what a writer's sample points into, and that its buffers are reused.

#include "common/transport/convert.h"

#include <gtest/gtest.h>

#include "tests/common/transport/test_samples.h"

namespace srics::transport::internal {
namespace {

// A writer converts message after message with one SequenceBuffers: after clear() the same
// slots hand out the same memory (no allocation per message), and what an earlier Hold of the
// same round returned stays valid while later ones grow the pool.
TEST(SequenceBuffersTest, ReusesItsMemoryAndKeepsEarlierSequencesValid) {
  SequenceBuffers buffers;
  float* first = buffers.Hold<float>(8);
  for (int i = 0; i < 8; ++i) first[i] = static_cast<float>(i);
  std::vector<float*> later;
  for (int k = 0; k < 40; ++k) later.push_back(buffers.Hold<float>(3));  // the pool grows
  int16_t* shorts = buffers.Hold<int16_t>(4);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(first[i], static_cast<float>(i)) << "an earlier sequence moved";
  buffers.clear();
  const float* again = buffers.Hold<float>(8);
  EXPECT_EQ(again, first);
  EXPECT_EQ(again[3], 3.0f) << "fresh memory (a new vector is zeroed): not reused";
  EXPECT_EQ(buffers.Hold<float>(2), later[0]);  // smaller: the same memory
  EXPECT_EQ(buffers.Hold<int16_t>(4), shorts);
}

// Doubles go out as floats through the buffers; converting the next message with the same
// buffers gives its own values, through the same memory.
TEST(SequenceBuffersTest, ConsecutiveMessagesThroughOneWriterBuffers) {
  SequenceBuffers buffers;
  const rl::EvalReport a = testing::MakeEvalResult(1), b = testing::MakeEvalResult(2);
  srics_EvalResult sample_a{}, sample_b{};
  ToC(a, {.run_id = "r"}, &sample_a, &buffers);
  const float* memory = sample_a.entity_distance._buffer;
  ASSERT_EQ(sample_a.entity_distance._length, a.summary.entity_distance.size());
  for (size_t i = 0; i < a.summary.entity_distance.size(); ++i)
    EXPECT_EQ(sample_a.entity_distance._buffer[i], static_cast<float>(a.summary.entity_distance[i]));
  ToC(b, {.run_id = "r"}, &sample_b, &buffers);
  EXPECT_EQ(sample_b.entity_distance._buffer, memory);
  rl::EvalReport back;
  FromC(sample_b, &back);
  ASSERT_EQ(back.summary.entity_distance.size(), b.summary.entity_distance.size());
  for (size_t i = 0; i < b.summary.entity_distance.size(); ++i)
    EXPECT_EQ(back.summary.entity_distance[i], static_cast<double>(static_cast<float>(b.summary.entity_distance[i])));
  EXPECT_EQ(back.policy_version, b.policy_version);
}

}  // namespace
}  // namespace srics::transport::internal
