#pragma once
// The MuJoCo 2.2 implementation of Environment: the "Multi-Object Rearrange" family of
// docs/method.md section 1, with its model generated from config (mjcf.h).
//
// Per env step: the action (clipped to [-1, 1]) moves the mocap to the hand's current xy +
// action_scale * action, z held at hand.z, clipped to the mocap box; then frame_skip physics
// steps, each followed by a check of MuJoCo's bad-number warnings; then static objects are
// put back to their initial xy (velocity zeroed) and every present object's xy is clipped to
// the table's object box.

#include <memory>

#include "actor/env/environment.h"
#include "common/config/env_config.h"

struct mjModel_;
struct mjData_;

namespace srics::env {

class RearrangeEnv final : public Environment {
 public:
  // Checks the config (std::invalid_argument naming the key on a broken rule, including
  // objects that cannot be placed with the spacing rules), generates and compiles the model
  // (MujocoError with MuJoCo's message), and resets with seed 0.
  explicit RearrangeEnv(const config::EnvConfig& config);
  ~RearrangeEnv() override;
  RearrangeEnv(const RearrangeEnv&) = delete;
  RearrangeEnv& operator=(const RearrangeEnv&) = delete;

  void Reset(uint64_t seed, Split split = Split::kTrain) override;
  StepStatus Step(std::span<const double> action) override;
  int action_dim() const override { return 2; }
  const EntityLayout& layout() const override { return layout_; }
  void GetStates(std::vector<double>* out) const override;
  std::vector<Vec2> Positions() const override;
  const std::vector<Vec2>& goals() const override { return goals_; }
  void SetGoals(std::span<const Vec2> goals) override;
  Metrics ComputeMetrics() const override;
  int steps() const override { return steps_; }
  bool unstable() const override { return unstable_; }

  // Catalogue entity numbers of the objects present in this episode (entity k of the
  // states is present()[k - 1]).
  const std::vector<int>& present() const { return present_; }
  // The objects' xy at Reset, in the order of present().
  const std::vector<Vec2>& initial_positions() const { return initial_; }
  const config::EnvConfig& config() const { return config_; }

  // The compiled model and its data, for tests and the benchmark (MuJoCo types).
  const mjModel_* model() const;
  mjData_* data();

 private:
  struct Mujoco;

  config::EnvConfig config_;
  std::vector<config::ObjectConfig> objects_;  // the catalogue, entities 1..n
  std::unique_ptr<Mujoco> mj_;
  std::vector<int> present_;
  std::vector<Vec2> initial_;
  std::vector<Vec2> goals_;
  EntityLayout layout_;
  int steps_ = 0;
  bool unstable_ = false;
};

// The environment for `config` behind the interface.
std::unique_ptr<Environment> MakeRearrangeEnv(const config::EnvConfig& config);

}  // namespace srics::env
