// Dumps our generated MJCF (default config, 1 puck) and runs the real RearrangeEnv with a
// constant action to cross-check the probe's reimplementation of the mocap rule.
#include <cstdio>
#include <fstream>
#include <mujoco/mujoco.h>
#include "actor/env/mjcf.h"
#include "actor/env/rearrange_env.h"
using namespace srics;
int main(int argc, char** argv) {
  config::EnvConfig c;
  c.num_pucks = 1;
  std::ofstream("/tmp/handprobe/ours.xml") << env::GenerateRearrangeMjcf(c);
  env::RearrangeEnv e(c);
  for (int dir = 0; dir < 2; ++dir) {
    e.Reset(1);
    mjData* d = e.data();
    const mjModel* m = e.model();
    // park the puck away
    int j = mj_name2id(m, mjOBJ_JOINT, "object1");
    d->qpos[m->jnt_qposadr[j]] = -2; d->qpos[m->jnt_qposadr[j]+1] = -2;
    mj_forward(m, d);
    double a[2] = {0, 0}; a[dir] = 1.0;
    // start the x run from the middle of the table, like the probe
    if (dir == 0) { int hj = mj_name2id(m, mjOBJ_JOINT, "hand"); }
    std::printf("dir %d\n", dir);
    for (int s = 0; s < 8; ++s) {
      e.Step(a);
      auto p = e.Positions();
      std::printf("  step %d hand %.4f %.4f\n", s + 1, p[0][0], p[0][1]);
    }
  }
}
