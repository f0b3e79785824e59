#include "common/rl/rewards.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace srics::rl {
namespace {

// Arm and three pucks, 4 kinds, no velocities: D = 6. Between the two states the arm moves
// 0.03, puck 1 is pushed 0.04, puck 2 drifts 0.12 and puck 3 moves 0.04.
class RewardsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    layout_ = {4, 4, false};
    before_ = State({{0, 0.4}, {0.1, 0.5}, {-0.1, 0.6}, {0.2, 0.45}});
    after_ = State({{0, 0.43}, {0.1, 0.54}, {0.02, 0.6}, {0.2, 0.49}});
  }
  std::vector<float> State(std::vector<std::pair<float, float>> xy) {
    std::vector<float> s(layout_.state_size(), 0.0f);
    for (int i = 0; i < layout_.num_entities; ++i) {
      s[i * layout_.entity_dim() + i] = 1.0f;  // one-hot identifier
      s[layout_.position_offset(i)] = xy[i].first;
      s[layout_.position_offset(i) + 1] = xy[i].second;
    }
    return s;
  }
  double Selectivity(int entity, std::vector<float> goal, uint64_t ancestors, config::SelectivityForm form,
                     const std::vector<float>* before = nullptr, const std::vector<float>* after = nullptr) {
    config::RewardConfig c;
    c.selectivity_form = form;
    return SelectivityReward(layout_, (before ? *before : before_).data(), (after ? *after : after_).data(), entity,
                             goal.data(), ancestors, c);
  }
  EntityLayout layout_;
  std::vector<float> before_, after_;
};

constexpr auto kReference = config::SelectivityForm::kReference;
constexpr auto kPaper = config::SelectivityForm::kPaper;
constexpr double kTol = 1e-6;

TEST_F(RewardsTest, UnsolvedSubgoalWithIndependentMotion) {
  // dist 0.16; own 0.04; independent pucks 2, 3: sum 0.16, mean 0.08
  // reference: sel = -1 + 0.04 / 0.12 = -2/3;  r = -0.16 - 0.25 * 2/3
  EXPECT_NEAR(Selectivity(1, {0.1f, 0.7f}, 0b1, kReference), -0.16 - 0.25 * 2.0 / 3.0, kTol);
  // paper: sel = 0.04 / 0.20 = 0.2;  r = -0.16 + 0.25 * (0.2 - 1)
  EXPECT_NEAR(Selectivity(1, {0.1f, 0.7f}, 0b1, kPaper), -0.16 - 0.25 * 0.8, kTol);
}

TEST_F(RewardsTest, SolvedSubgoalPenalisesOnlyIndependentMotion) {
  // dist 0.01 < 0.05; reference: r = -0.01 - mean 0.08; paper: sel = 1 - 0.16
  EXPECT_NEAR(Selectivity(1, {0.1f, 0.55f}, 0b1, kReference), -0.01 - 0.08, kTol);
  EXPECT_NEAR(Selectivity(1, {0.1f, 0.55f}, 0b1, kPaper), -0.01 + 0.25 * (0.84 - 1.0), kTol);
}

// agent.reward.disturbance_weight: minus beta times the summed motion of the independent
// entities, on every step, solved or not, in both forms; the ancestors' motion is free
TEST_F(RewardsTest, DisturbanceTermChargesEveryIndependentMotion) {
  config::RewardConfig c;
  c.disturbance_weight = 10;
  for (auto form : {kReference, kPaper}) {
    c.selectivity_form = form;
    for (std::vector<float> goal : {std::vector<float>{0.1f, 0.7f}, std::vector<float>{0.1f, 0.55f}}) {
      // pucks 2 and 3 moved 0.12 + 0.04 = 0.16: 10 x 0.16 = 1.6 below the form's reward
      EXPECT_NEAR(SelectivityReward(layout_, before_.data(), after_.data(), 1, goal.data(), 0b1, c),
                  Selectivity(1, goal, 0b1, form) - 1.6, kTol);
      // puck 2 an ancestor too: only puck 3's 0.04 is charged
      c.disturbance_weight = 0;
      const double without = SelectivityReward(layout_, before_.data(), after_.data(), 1, goal.data(), 0b101, c);
      c.disturbance_weight = 10;
      EXPECT_NEAR(SelectivityReward(layout_, before_.data(), after_.data(), 1, goal.data(), 0b101, c), without - 0.4,
                  kTol);
    }
  }
  // the hand alone moving onto a solved puck's neighbour: the form sees nothing of puck 3's
  // push while puck 1 stands still (reference: sel = -1 whether or not puck 3 moves)
  const std::vector<float> pushed = State({{0.2, 0.45}, {0.1, 0.5}, {-0.1, 0.6}, {0.2, 0.49}});
  const std::vector<float> still = State({{0.2, 0.45}, {0.1, 0.5}, {-0.1, 0.6}, {0.2, 0.45}});
  c.selectivity_form = kReference;
  c.disturbance_weight = 0;
  EXPECT_NEAR(SelectivityReward(layout_, still.data(), pushed.data(), 1, std::vector<float>{0.1f, 0.7f}.data(), 0b1, c),
              SelectivityReward(layout_, still.data(), still.data(), 1, std::vector<float>{0.1f, 0.7f}.data(), 0b1, c),
              kTol);
  c.disturbance_weight = 10;
  EXPECT_NEAR(
      SelectivityReward(layout_, still.data(), pushed.data(), 1, std::vector<float>{0.1f, 0.7f}.data(), 0b1, c),
      SelectivityReward(layout_, still.data(), still.data(), 1, std::vector<float>{0.1f, 0.7f}.data(), 0b1, c) - 0.4,
      kTol);
}

TEST_F(RewardsTest, ArmSubgoalCountsEveryPuckAsIndependent) {
  // arm: dist 0.03 (solved), others {1, 2, 3} moved 0.04 + 0.12 + 0.04
  EXPECT_NEAR(Selectivity(0, {0.0f, 0.4f}, 0, kReference), -0.03 - 0.2 / 3.0, kTol);
  EXPECT_NEAR(Selectivity(0, {0.0f, 0.4f}, 0, kPaper), -0.03 - 0.25 * 0.2, kTol);
}

TEST_F(RewardsTest, NoIndependentEntities) {
  // every other entity is an ancestor: selectivity is perfect, only distance remains
  EXPECT_NEAR(Selectivity(1, {0.1f, 0.7f}, 0b1101, kReference), -0.16, kTol);
  EXPECT_NEAR(Selectivity(1, {0.1f, 0.7f}, 0b1101, kPaper), -0.16, kTol);
}

TEST_F(RewardsTest, NothingMovedIsTheEpsilonCase) {
  // dist 0.2, no motion at all: the selectivity term is its worst (-alpha) in both forms
  EXPECT_NEAR(Selectivity(1, {0.1f, 0.7f}, 0b1, kReference, &before_, &before_), -0.2 - 0.25, kTol);
  EXPECT_NEAR(Selectivity(1, {0.1f, 0.7f}, 0b1, kPaper, &before_, &before_), -0.2 - 0.25, kTol);
}

TEST_F(RewardsTest, DistanceAndFullGoalRewards) {
  std::vector<float> goal = {0.1f, 0.7f};
  EXPECT_NEAR(DistanceReward(layout_, after_.data(), 1, goal.data()), -0.16, kTol);
  // full goal = the state before: per-entity offsets 0.03, 0.04, 0.12, 0.04
  std::vector<float> full = {0, 0.4f, 0.1f, 0.5f, -0.1f, 0.6f, 0.2f, 0.45f};
  EXPECT_NEAR(FullGoalReward(layout_, after_.data(), full.data()),
              -std::sqrt(0.03 * 0.03 + 0.04 * 0.04 + 0.12 * 0.12 + 0.04 * 0.04), kTol);
}

// A tied pair attempted as one (pucks 1 and 3, goal 2 floats each): distance and own motion
// summed over both, solved only when both are within the threshold, the partner's motion
// never independent.
TEST_F(RewardsTest, APairSumsItsDistancesAndMotionsAndIsSolvedWhenBothAre) {
  config::RewardConfig c;
  c.selectivity_form = kPaper;
  const SubgoalUnit pair(1, 3);
  // after: puck 1 at (0.1, 0.54), puck 3 at (0.2, 0.49); distances 0.16 and 0.01
  const std::vector<float> goal = {0.1f, 0.7f, 0.2f, 0.5f};
  // own 0.04 + 0.04; independent: puck 2 only (the arm an ancestor): 0.12
  // paper: sel = 0.08 / 0.20 = 0.4; r = -0.17 + 0.25 * (0.4 - 1)
  EXPECT_NEAR(SelectivityReward(layout_, before_.data(), after_.data(), pair, goal.data(), 0b1, c),
              -0.17 + 0.25 * (0.4 - 1.0), kTol);
  // both within 0.05 (0.01 each): solved, sel = 1 - 0.12
  const std::vector<float> near = {0.1f, 0.55f, 0.2f, 0.5f};
  EXPECT_NEAR(SelectivityReward(layout_, before_.data(), after_.data(), pair, near.data(), 0b1, c),
              -0.02 + 0.25 * (0.88 - 1.0), kTol);
  // one member outside the threshold (puck 1 at 0.06, puck 3 at 0.01): unsolved
  const std::vector<float> one_far = {0.1f, 0.60f, 0.2f, 0.5f};
  EXPECT_NEAR(SelectivityReward(layout_, before_.data(), after_.data(), pair, one_far.data(), 0b1, c),
              -0.07 + 0.25 * (0.4 - 1.0), kTol);
  EXPECT_NEAR(DistanceReward(layout_, after_.data(), pair, goal.data()), -0.17, kTol);
  // measure: 0.08 / (0.08 + 0.12)
  EXPECT_NEAR(*SelectivityMeasure(layout_, before_.data(), after_.data(), pair, 0b1, 1e-9), 0.4, kTol);
}

TEST_F(RewardsTest, SelectivityMeasure) {
  auto m = SelectivityMeasure(layout_, before_.data(), after_.data(), 1, 0b1, 1e-5);
  ASSERT_TRUE(m.has_value());
  EXPECT_NEAR(*m, 0.04 / (0.04 + 0.08), kTol);
  EXPECT_FALSE(SelectivityMeasure(layout_, before_.data(), before_.data(), 1, 0b1, 1e-5));
}

}  // namespace
}  // namespace srics::rl
