// MuJoCo plumbing: errors throw with MuJoCo's message instead of exiting; models load from
// memory.

#include <gtest/gtest.h>

#include "actor/env/mjcf.h"
#include "actor/env/mujoco_util.h"

namespace srics::env {
namespace {

constexpr char kFallingBox[] = R"(
<mujoco>
  <worldbody>
    <geom type="plane" size="1 1 0.1"/>
    <body pos="0 0 0.5"><freejoint/><geom type="box" size="0.05 0.05 0.05" mass="1"/></body>
  </worldbody>
</mujoco>)";

TEST(MujocoUtilTest, LoadsInlineModelAndSimulates) {
  ModelPtr model = LoadModelFromXml(kFallingBox);
  DataPtr data = MakeData(model.get());
  for (int i = 0; i < 1000; ++i) mj_step(model.get(), data.get());
  // the box fell and rests on the plane
  EXPECT_NEAR(data->qpos[2], 0.05, 0.005);
  EXPECT_FALSE(HasInstabilityWarning(data.get()));
}

TEST(MujocoUtilTest, BadMjcfThrowsWithMujocosMessage) {
  try {
    LoadModelFromXml("<mujoco><worldbody><geom type=\"sphere\" sise=\"1\"/></worldbody></mujoco>");
    FAIL() << "expected MujocoError";
  } catch (const MujocoError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("MJCF error: ", 0), 0u) << message;
    EXPECT_NE(message.find("sise"), std::string::npos) << message;  // MuJoCo names the attribute
  }
  EXPECT_THROW(LoadModelFromXml("not xml at all"), MujocoError);
}

TEST(MujocoUtilTest, FatalEngineErrorThrowsInsteadOfExiting) {
  InstallMujocoHandlers();
  EXPECT_THROW(mju_error("a fatal error"), MujocoError);
  try {
    mju_error("boom");
  } catch (const MujocoError& e) {
    EXPECT_NE(std::string(e.what()).find("boom"), std::string::npos);
  }
}

TEST(MujocoUtilTest, BlowUpIsFlaggedByTheWarningCounters) {
  ModelPtr model = LoadModelFromXml(kFallingBox);
  DataPtr data = MakeData(model.get());
  data->qvel[0] = 1e12;  // beyond mjMAXVAL: MuJoCo resets the data and counts a warning
  mj_step(model.get(), data.get());
  EXPECT_TRUE(HasInstabilityWarning(data.get()));
}

TEST(MujocoUtilTest, EveryPresetShapeCompiles) {
  config::EnvConfig c;
  c.objects.resize(2);
  c.objects[1].shape = config::ObjectShape::kBox;
  config::ConnectionConfig spring;
  spring.first = 1;
  spring.second = 2;
  spring.kind = config::ConnectionKind::kSpring;
  c.connections.push_back(spring);
  ModelPtr model = LoadModelFromXml(GenerateRearrangeMjcf(c));
  EXPECT_EQ(model->ntendon, 1);
  EXPECT_EQ(model->nmocap, 1);
  EXPECT_DOUBLE_EQ(model->opt.timestep, 0.002);
  EXPECT_EQ(model->opt.integrator, mjINT_EULER);
  EXPECT_EQ(model->opt.iterations, 50);
  EXPECT_EQ(model->geom_type[mj_name2id(model.get(), mjOBJ_GEOM, "object2")], mjGEOM_BOX);
  // the configured mass and inertia, not the geom's density-derived ones
  const int body = mj_name2id(model.get(), mjOBJ_BODY, "object1");
  EXPECT_NEAR(model->body_mass[body], 0.1, 1e-12);
  EXPECT_NEAR(model->body_inertia[3 * body], 100000.0, 1e-6);
  EXPECT_NEAR(model->body_mass[mj_name2id(model.get(), mjOBJ_BODY, "hand")], c.hand.mass, 1e-12);
}

}  // namespace
}  // namespace srics::env
