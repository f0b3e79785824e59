// The checks of what actors and the learner receive as plain data (common/rl/updates.h).

#include "common/rl/updates.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/rl/episode.h"

namespace srics::rl {
namespace {

TEST(ParameterProblemTest, FiniteAndWithinTheBound) {
  std::vector<float> p = {0.0f, -1.5f, kMaxAbsParameter, -kMaxAbsParameter};
  EXPECT_EQ(ParameterProblem(p), "");
  p[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(ParameterProblem(p).find("parameter 1 is not finite"), std::string::npos);
  p[1] = 1.0f;
  p[2] = 1e30f;
  EXPECT_NE(ParameterProblem(p).find("parameter 2"), std::string::npos);
  p[2] = -std::numeric_limits<float>::infinity();
  EXPECT_NE(ParameterProblem(p).find("not finite"), std::string::npos);
}

// A LearnerStats sample from anyone ended every actor, or held it back forever: the actors
// now act only on progress that can be their run's learner's.
TEST(ImplausibleProgressTest, OnlyTheRunsBudgetAndConsistentCounters) {
  const uint64_t budget = 60000;
  LearnerProgress p{.updates = 100,
                    .transitions_inserted = 5000,
                    .policy_version = 3,
                    .training_env_steps = 4000,
                    .budget_env_steps = budget,
                    .replay_size = 5000};
  EXPECT_EQ(ImplausibleProgress(p, budget), "");
  LearnerProgress done = p;
  done.training_env_steps = done.transitions_inserted = budget + 20;  // the last episode overshoots
  EXPECT_EQ(ImplausibleProgress(done, budget), "");
  EXPECT_TRUE(done.budget_done());

  LearnerProgress q = p;
  q.budget_env_steps = 100;
  EXPECT_NE(ImplausibleProgress(q, budget).find("budget"), std::string::npos);
  q = p;
  q.training_env_steps = q.transitions_inserted = uint64_t{1} << 62;
  EXPECT_NE(ImplausibleProgress(q, budget).find("beyond the budget"), std::string::npos);
  q = p;
  q.training_env_steps = budget;  // "done" with fewer transitions than that
  EXPECT_NE(ImplausibleProgress(q, budget).find("transitions_inserted"), std::string::npos);
  q = p;
  q.replay_size = 6000;
  EXPECT_NE(ImplausibleProgress(q, budget).find("replay_size"), std::string::npos);
  // a backlog that is no count of updates would hold every actor back (or never)
  for (double backlog : {std::nan(""), double(INFINITY), -double(INFINITY), 1e16, -1e16}) {
    q = p;
    q.update_backlog = backlog;
    EXPECT_NE(ImplausibleProgress(q, budget).find("update_backlog"), std::string::npos) << backlog;
  }
  q = p;
  q.update_backlog = -2.5;  // a learner ahead within its error buffer
  EXPECT_EQ(ImplausibleProgress(q, budget), "");
  // a run without a budget (0) accepts any step count that is consistent
  LearnerProgress unbounded = p;
  unbounded.budget_env_steps = 0;
  unbounded.training_env_steps = unbounded.transitions_inserted = unbounded.replay_size = uint64_t{1} << 40;
  EXPECT_EQ(ImplausibleProgress(unbounded, 0), "");
}

}  // namespace
}  // namespace srics::rl
