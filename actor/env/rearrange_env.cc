#include "actor/env/rearrange_env.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "actor/env/metrics.h"
#include "actor/env/mjcf.h"
#include "actor/env/mujoco_util.h"
#include "actor/env/sampling.h"

namespace srics::env {

// Model, data and the addresses the hot path needs.
struct RearrangeEnv::Mujoco {
  ModelPtr model;
  DataPtr data;
  int hand_qpos = 0;
  int hand_dof = 0;
  int mocap = 0;
  // per catalogue object (index entity - 1): a free body's qpos and dof addresses (-1 for a
  // fixed static object), a fixed static object's mocap index (-1 for the others)
  std::vector<int> object_qpos;
  std::vector<int> object_dof;
  std::vector<int> object_mocap;

  // object i's xyz: its free joint's position or its mocap position
  mjtNum* ObjectPos(size_t i) const {
    return object_mocap[i] >= 0 ? data->mocap_pos + 3 * object_mocap[i] : data->qpos + object_qpos[i];
  }
};

namespace {

int FindId(const mjModel* m, mjtObj type, const std::string& name) {
  const int id = mj_name2id(m, type, name.c_str());
  if (id < 0) throw MujocoError("generated model has no '" + name + "'");
  return id;
}

}  // namespace

RearrangeEnv::RearrangeEnv(const config::EnvConfig& config)
    : config_(config), objects_(config::EffectiveObjects(config)), mj_(new Mujoco) {
  if (auto problem = config::CheckEnvConfig(config_); !problem.ok())
    throw std::invalid_argument("env config: " + problem.key + ": " + problem.message);
  // every object set must be placeable: try once, so that a crowded table fails here
  for (const auto* sets : {&config_.object_sets, &config_.eval_object_sets}) {
    std::vector<std::vector<int>> all = *sets;
    if (all.empty()) {
      Rng unused(0);
      all.push_back(SampleObjectSet(config_, false, unused));
    }
    for (const auto& set : all) {
      Rng rng(0);
      try {
        const auto initial = SampleInitialPositions(config_, set, rng);
        SampleGoals(config_, set, initial, rng);
      } catch (const SamplingError& e) {
        throw std::invalid_argument("env config: objects: more objects than fit the table with the spacing rules (" +
                                    std::string(e.what()) + ")");
      }
    }
  }

  mj_->model = LoadModelFromXml(GenerateRearrangeMjcf(config_));
  mj_->data = MakeData(mj_->model.get());
  const mjModel* m = mj_->model.get();
  const int hand_joint = FindId(m, mjOBJ_JOINT, "hand");
  mj_->hand_qpos = m->jnt_qposadr[hand_joint];
  mj_->hand_dof = m->jnt_dofadr[hand_joint];
  mj_->mocap = m->body_mocapid[FindId(m, mjOBJ_BODY, "mocap")];
  for (size_t i = 0; i < objects_.size(); ++i) {
    const std::string name = "object" + std::to_string(i + 1);
    const int mocap = m->body_mocapid[FindId(m, mjOBJ_BODY, name)];
    mj_->object_mocap.push_back(mocap);
    const int joint = mocap >= 0 ? -1 : FindId(m, mjOBJ_JOINT, name);
    mj_->object_qpos.push_back(joint >= 0 ? m->jnt_qposadr[joint] : -1);
    mj_->object_dof.push_back(joint >= 0 ? m->jnt_dofadr[joint] : -1);
  }
  Reset(0);
}

RearrangeEnv::~RearrangeEnv() = default;

const mjModel_* RearrangeEnv::model() const { return mj_->model.get(); }
mjData_* RearrangeEnv::data() { return mj_->data.get(); }

void RearrangeEnv::Reset(uint64_t seed, Split split) {
  // the episode is a function of the seed alone
  Rng rng(seed);
  present_ = SampleObjectSet(config_, split == Split::kEval, rng);
  initial_ = SampleInitialPositions(config_, present_, rng);
  goals_ = SampleGoals(config_, present_, initial_, rng);

  // clean data (time, warm start, warning counters), then place hand, mocap and objects
  const mjModel* m = mj_->model.get();
  mjData* d = mj_->data.get();
  mj_resetData(m, d);
  const double hand_pos[3] = {config_.hand.start[0], config_.hand.start[1], config_.hand.z};
  mjtNum* hq = d->qpos + mj_->hand_qpos;
  hq[0] = hand_pos[0], hq[1] = hand_pos[1], hq[2] = hand_pos[2];
  hq[3] = 1, hq[4] = 0, hq[5] = 0, hq[6] = 0;
  mjtNum* mp = d->mocap_pos + 3 * mj_->mocap;
  mp[0] = hand_pos[0], mp[1] = hand_pos[1], mp[2] = hand_pos[2];
  mjtNum* mq = d->mocap_quat + 4 * mj_->mocap;
  mq[0] = 1, mq[1] = 0, mq[2] = 0, mq[3] = 0;
  for (size_t i = 0; i < objects_.size(); ++i) {
    const int e = static_cast<int>(i) + 1;
    Vec2 xy = ParkingPosition(config_, e);
    for (size_t k = 0; k < present_.size(); ++k)
      if (present_[k] == e) xy = initial_[k];
    mjtNum* q = mj_->ObjectPos(i);
    q[0] = xy[0], q[1] = xy[1], q[2] = objects_[i].half_height;
    // a free joint's orientation follows its position; a mocap body's is mocap_quat
    mjtNum* quat = mj_->object_mocap[i] >= 0 ? d->mocap_quat + 4 * mj_->object_mocap[i] : q + 3;
    quat[0] = 1, quat[1] = 0, quat[2] = 0, quat[3] = 0;
  }
  mj_forward(m, d);

  // entity layout of this episode
  layout_.num_entities = 1 + static_cast<int>(present_.size());
  layout_.num_kinds = 1 + static_cast<int>(objects_.size());
  layout_.velocities = config_.velocities;
  layout_.entity_dim = layout_.num_kinds + (config_.velocities ? 4 : 2);
  layout_.kinds.assign(1, 0);
  layout_.kinds.insert(layout_.kinds.end(), present_.begin(), present_.end());
  steps_ = 0;
  unstable_ = false;
}

StepStatus RearrangeEnv::Step(std::span<const double> action) {
  if (unstable_) throw std::logic_error("RearrangeEnv::Step after an unstable step: call Reset");
  if (action.size() != 2)
    throw std::invalid_argument("RearrangeEnv::Step: expected 2 action components, got " +
                                std::to_string(action.size()));
  if (!std::isfinite(action[0]) || !std::isfinite(action[1]))
    throw std::invalid_argument("RearrangeEnv::Step: non-finite action");
  const mjModel* m = mj_->model.get();
  mjData* d = mj_->data.get();
  const auto& h = config_.hand;

  // mocap = hand xy + scaled action, z held, clipped to the mocap box
  const mjtNum* hq = d->qpos + mj_->hand_qpos;
  mjtNum* mp = d->mocap_pos + 3 * mj_->mocap;
  for (int a = 0; a < 2; ++a) {
    const double target = hq[a] + h.action_scale * std::clamp(action[a], -1.0, 1.0);
    mp[a] = std::clamp(target, h.mocap_low[a], h.mocap_high[a]);
  }
  mp[2] = h.z;

  // physics; a blow-up (MuJoCo resets its data and counts a warning) ends the episode
  unstable_ = true;  // stays set if MuJoCo throws mid-step
  for (int k = 0; k < config_.physics.frame_skip; ++k) {
    mj_step(m, d);
    if (HasInstabilityWarning(d)) return StepStatus::kUnstable;
  }
  unstable_ = false;

  // static objects back to their initial xy; every present object's xy into the object box
  const auto& t = config_.table;
  for (size_t k = 0; k < present_.size(); ++k) {
    const int i = present_[k] - 1;
    if (mj_->object_mocap[i] >= 0) continue;  // fixed: nothing moved it
    mjtNum* q = d->qpos + mj_->object_qpos[i];
    if (objects_[i].is_static) {
      q[0] = initial_[k][0], q[1] = initial_[k][1];
      std::fill(d->qvel + mj_->object_dof[i], d->qvel + mj_->object_dof[i] + 6, 0.0);
    }
    q[0] = std::clamp(q[0], t.object_low[0], t.object_high[0]);
    q[1] = std::clamp(q[1], t.object_low[1], t.object_high[1]);
  }
  ++steps_;
  return StepStatus::kOk;
}

void RearrangeEnv::GetStates(std::vector<double>* out) const {
  const mjData* d = mj_->data.get();
  const int n = layout_.num_entities, dim = layout_.entity_dim, k0 = layout_.num_kinds;
  out->assign(static_cast<size_t>(n) * dim, 0.0);
  for (int j = 0; j < n; ++j) {
    double* row = out->data() + static_cast<size_t>(j) * dim;
    row[layout_.kinds[j]] = 1.0;
    const int dof = j == 0 ? mj_->hand_dof : mj_->object_dof[present_[j - 1] - 1];
    const mjtNum* pos = j == 0 ? d->qpos + mj_->hand_qpos : mj_->ObjectPos(present_[j - 1] - 1);
    row[k0] = pos[0];
    row[k0 + 1] = pos[1];
    if (layout_.velocities && dof >= 0) {  // a fixed object's velocity is 0
      // a free joint's first three velocities are linear, in the world frame
      row[k0 + 2] = d->qvel[dof];
      row[k0 + 3] = d->qvel[dof + 1];
    }
  }
}

std::vector<Vec2> RearrangeEnv::Positions() const {
  const mjData* d = mj_->data.get();
  std::vector<Vec2> out(present_.size() + 1);
  out[0] = {d->qpos[mj_->hand_qpos], d->qpos[mj_->hand_qpos + 1]};
  for (size_t k = 0; k < present_.size(); ++k) {
    const mjtNum* q = mj_->ObjectPos(present_[k] - 1);
    out[k + 1] = {q[0], q[1]};
  }
  return out;
}

void RearrangeEnv::SetGoals(std::span<const Vec2> goals) {
  if (goals.size() != goals_.size())
    throw std::invalid_argument("RearrangeEnv::SetGoals: expected " + std::to_string(goals_.size()) + " goals, got " +
                                std::to_string(goals.size()));
  goals_.assign(goals.begin(), goals.end());
}

Metrics RearrangeEnv::ComputeMetrics() const {
  const auto positions = Positions();
  return env::ComputeMetrics(positions, goals_, config_.success_threshold);
}

std::unique_ptr<Environment> MakeRearrangeEnv(const config::EnvConfig& config) {
  return std::make_unique<RearrangeEnv>(config);
}

}  // namespace srics::env
