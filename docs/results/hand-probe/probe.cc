// Hand probe: the reference (multiworld SawyerMultiobjectPushEnv, sawyer_push_multiobj.xml) vs
// our generated model (ours.xml, dumped by dump_ours from the project's env library).
// Each env reproduces its own mocap rule; see hand-probe.md for the sources.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

static const char* kRefXml =
    "/tmp/ref/multiworld/multiworld/envs/assets/multi_object_sawyer_xyz/probe_root.xml";
static const char* kOursXml = "/tmp/handprobe/ours.xml";
static bool g_normalized_quat = false;  // diagnostic only: the python sets (1, 0, 1, 0)

struct Box3 {
  double lo[3], hi[3];
};

// world AABB of a geom
static Box3 GeomAabb(const mjModel* m, const mjData* d, int g) {
  const double* p = d->geom_xpos + 3 * g;
  const double* R = d->geom_xmat + 9 * g;
  const double* s = m->geom_size + 3 * g;
  double e[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    switch (m->geom_type[g]) {
      case mjGEOM_BOX:
        e[i] = std::fabs(R[3 * i]) * s[0] + std::fabs(R[3 * i + 1]) * s[1] + std::fabs(R[3 * i + 2]) * s[2];
        break;
      case mjGEOM_CYLINDER: {
        const double a = R[3 * i + 2];
        e[i] = std::fabs(a) * s[1] + s[0] * std::sqrt(std::max(0.0, 1 - a * a));
        break;
      }
      case mjGEOM_CAPSULE:
        e[i] = std::fabs(R[3 * i + 2]) * s[1] + s[0];
        break;
      case mjGEOM_SPHERE:
        e[i] = s[0];
        break;
      default:
        e[i] = m->geom_rbound[g];
    }
  }
  Box3 b;
  for (int i = 0; i < 3; ++i) b.lo[i] = p[i] - e[i], b.hi[i] = p[i] + e[i];
  return b;
}

static bool CanCollide(const mjModel* m, int a, int b) {
  return (m->geom_contype[a] & m->geom_conaffinity[b]) || (m->geom_contype[b] & m->geom_conaffinity[a]);
}

struct Env {
  std::string name;
  bool ref = false;
  mjModel* m = nullptr;
  mjData* d = nullptr;
  int hand_body = -1;   // the welded body (leftclaw / hand)
  int mocap = -1;       // mocap index
  int table = -1;       // table geom
  std::vector<int> hand_geoms;  // collidable geoms rigidly attached to the hand body
  std::vector<int> arm_geoms;   // every collidable geom of a moving body that is not a puck
  std::vector<int> pucks;       // puck bodies
  std::vector<int> puck_geom, puck_qpos, puck_dof;
  std::vector<double> saved_qpos, saved_qvel, saved_act;  // reference reset state
  double time0 = 0;
  // the reference reads body_xpos/xquat right after sim.step: they are one substep stale
  double stale_pos[3] = {0, 0, 0}, stale_quat[4] = {1, 0, 0, 0};
  bool have_stale = false;
  bool setup_done = false;

  // per env step statistics (filled by Step)
  double peak_speed = 0;        // max over substeps of |d hand xy| / dt
  int table_contact_substeps = 0;
  double table_force_sum = 0;   // summed normal force of hand-table contacts (mean over substeps)
  double max_table_pen = 0;     // deepest hand-table penetration
  int puck_contact_substeps = 0;
  std::vector<std::string> other_contacts;  // arm geom contacts other than table/puck
  std::vector<int> puck_contact_geoms;      // hand geoms that touched a puck

  double mocap_z_old() const { return d->mocap_pos[3 * mocap + 2]; }

  void Init(const std::string& n, const char* path, bool is_ref) {
    name = n;
    ref = is_ref;
    char err[1000] = "";
    m = mj_loadXML(path, nullptr, err, sizeof(err));
    if (!m) {
      std::fprintf(stderr, "load %s: %s\n", path, err);
      std::exit(1);
    }
    d = mj_makeData(m);
    hand_body = mj_name2id(m, mjOBJ_BODY, ref ? "leftclaw" : "hand");
    mocap = m->body_mocapid[mj_name2id(m, mjOBJ_BODY, "mocap")];
    table = mj_name2id(m, mjOBJ_GEOM, ref ? "tableTop" : "table");
    for (int i = 0; i < 3; ++i) {
      const std::string on = "object" + std::to_string(ref ? i : i + 1);
      const int b = mj_name2id(m, mjOBJ_BODY, on.c_str());
      if (b < 0) break;
      pucks.push_back(b);
      puck_geom.push_back(mj_name2id(m, mjOBJ_GEOM, on.c_str()));
      const int j = m->body_jntadr[b];
      puck_qpos.push_back(m->jnt_qposadr[j]);
      puck_dof.push_back(m->jnt_dofadr[j]);
    }
    const int hw = m->body_weldid[hand_body];
    for (int g = 0; g < m->ngeom; ++g) {
      const int b = m->geom_bodyid[g];
      if (!(m->geom_contype[g] || m->geom_conaffinity[g])) continue;
      if (m->body_weldid[b] == 0) continue;  // world
      if (std::find(pucks.begin(), pucks.end(), b) != pucks.end()) continue;
      arm_geoms.push_back(g);
      if (m->body_weldid[b] == hw) hand_geoms.push_back(g);
    }
  }

  std::string GName(int g) const {
    const char* s = mj_id2name(m, mjOBJ_GEOM, g);
    if (s) return s;
    return std::string(mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[g])) + "#" + std::to_string(g);
  }

  void ParkPucks() {
    for (size_t i = 0; i < pucks.size(); ++i) SetPuck(i, -10 - 0.5 * i, -10 + 0.0 * i);
  }
  void SetPuck(size_t i, double x, double y) {
    double* q = d->qpos + puck_qpos[i];
    q[0] = x, q[1] = y, q[2] = ref ? 0.02 : 0.015;
    q[3] = 1, q[4] = q[5] = q[6] = 0;
    std::fill(d->qvel + puck_dof[i], d->qvel + puck_dof[i] + 6, 0.0);
    have_stale = false;  // the caller runs mj_forward
  }
  const double* PuckPos(size_t i) const { return d->xpos + 3 * pucks[i]; }
  const double* HandPos() const { return d->xpos + 3 * hand_body; }

  void ResetWelds() {
    for (int i = 0; i < m->neq; ++i)
      if (m->eq_type[i] == mjEQ_WELD) {
        double* e = m->eq_data + mjNEQDATA * i;
        // the reference's _reset_mocap_welds: relpose (0 0 0, 1 0 0 0); MuJoCo 2.2 adds
        // anchor (3, zero) before it and torquescale (1) after it
        const double v[11] = {0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1};
        std::memcpy(e, v, sizeof(v));
      }
    mj_forward(m, d);
  }

  // the environment's reset (a fresh episode): reference = restore _env_setup's state
  void Reset() {
    if (ref) {
      if (!setup_done) {  // _env_setup, once
        mj_resetData(m, d);
        const double arm[7] = {1.78026069e+00, -6.84415781e-01, -1.54549231e-01, 2.30672090e+00,
                               1.93111471e+00, 1.27854012e-01,  1.49353907e+00};
        for (int i = 0; i < 7; ++i) d->qpos[i] = arm[i];
        ResetWelds();
        double* mp = d->mocap_pos + 3 * mocap;
        mp[0] = 0, mp[1] = 0.4, mp[2] = 0.02;
        double* mq = d->mocap_quat + 4 * mocap;
        mq[0] = 1, mq[1] = 0, mq[2] = 1, mq[3] = 0;
        for (int k = 0; k < 10; ++k) mj_step(m, d);
        ParkPucks();
        ResetWelds();
        saved_qpos.assign(d->qpos, d->qpos + m->nq);
        saved_qvel.assign(d->qvel, d->qvel + m->nv);
        time0 = d->time;
        setup_done = true;
      }
      // reset(): set_state (qpos, qvel, time; mocap untouched) + forward. We also put the mocap
      // back where it was at the first reset, so that every probe starts alike.
      std::copy(saved_qpos.begin(), saved_qpos.end(), d->qpos);
      std::copy(saved_qvel.begin(), saved_qvel.end(), d->qvel);
      d->time = time0;
      double* mp = d->mocap_pos + 3 * mocap;
      mp[0] = 0, mp[1] = 0.4, mp[2] = 0.02;
      double* mq = d->mocap_quat + 4 * mocap;
      mq[0] = 1, mq[1] = 0, mq[2] = 1, mq[3] = 0;
      std::fill(d->qacc_warmstart, d->qacc_warmstart + m->nv, 0.0);
      mj_forward(m, d);
    } else {
      mj_resetData(m, d);
      const int hj = m->body_jntadr[hand_body];
      double* hq = d->qpos + m->jnt_qposadr[hj];
      hq[0] = 0, hq[1] = 0.4, hq[2] = 0.02, hq[3] = 1, hq[4] = hq[5] = hq[6] = 0;
      double* mp = d->mocap_pos + 3 * mocap;
      mp[0] = 0, mp[1] = 0.4, mp[2] = 0.02;
      ParkPucks();
      mj_forward(m, d);
    }
    ParkPucks();
    mj_forward(m, d);
    have_stale = false;
  }

  // one env step with action a (the env's own mocap rule)
  void Step(double ax, double ay) {
    ax = std::clamp(ax, -1.0, 1.0), ay = std::clamp(ay, -1.0, 1.0);
    double* mp = d->mocap_pos + 3 * mocap;
    if (ref) {
      // _set_action: dz from the OLD mocap z, then _reset_mocap2body_xpos, then add, clip
      const double dz = 0.02 - mp[2];
      const double* hp = have_stale ? stale_pos : d->xpos + 3 * hand_body;
      const double* hq = have_stale ? stale_quat : d->xquat + 4 * hand_body;
      double* mq = d->mocap_quat + 4 * mocap;
      for (int i = 0; i < 3; ++i) mp[i] = hp[i];
      for (int i = 0; i < 4; ++i) mq[i] = hq[i];
      const double lo[3] = {-0.245, 0.40, 0.0}, hi[3] = {0.245, 0.75, 0.5};
      const double delta[3] = {0.1 * ax, 0.1 * ay, dz};
      for (int i = 0; i < 3; ++i) mp[i] = std::clamp(mp[i] + delta[i], lo[i], hi[i]);
      mq[0] = 1, mq[1] = 0, mq[2] = 1, mq[3] = 0;
      if (g_normalized_quat) mq[0] = mq[2] = std::sqrt(0.5);
    } else {
      const int hj = m->body_jntadr[hand_body];
      const double* hq = d->qpos + m->jnt_qposadr[hj];
      const double lo[2] = {-0.245, 0.40}, hi[2] = {0.245, 0.75};
      const double a[2] = {ax, ay};
      for (int i = 0; i < 2; ++i) mp[i] = std::clamp(hq[i] + 0.1 * a[i], lo[i], hi[i]);
      mp[2] = 0.02;
    }
    peak_speed = 0;
    table_contact_substeps = 0;
    table_force_sum = 0;
    max_table_pen = 0;
    puck_contact_substeps = 0;
    other_contacts.clear();
    puck_contact_geoms.clear();
    for (int k = 0; k < 50; ++k) {
      const double x0 = HandPos()[0], y0 = HandPos()[1];
      mj_step(m, d);
      // xpos is from the start of this substep: consecutive values are one substep apart
      const double v = std::hypot(HandPos()[0] - x0, HandPos()[1] - y0) / m->opt.timestep;
      peak_speed = std::max(peak_speed, v);
      bool tc = false, pc = false;
      for (int c = 0; c < d->ncon; ++c) {
        const mjContact& con = d->contact[c];
        const bool a1 = std::find(arm_geoms.begin(), arm_geoms.end(), con.geom1) != arm_geoms.end();
        const bool a2 = std::find(arm_geoms.begin(), arm_geoms.end(), con.geom2) != arm_geoms.end();
        if (!a1 && !a2) continue;
        const int ag = a1 ? con.geom1 : con.geom2, other = a1 ? con.geom2 : con.geom1;
        if (other == table) {
          tc = true;
          double f[6];
          mj_contactForce(m, d, c, f);
          table_force_sum += f[0];
          max_table_pen = std::max(max_table_pen, -con.dist);
          if (std::find(hand_geoms.begin(), hand_geoms.end(), ag) == hand_geoms.end()) {
            std::string s = GName(ag) + "-table";
            if (std::find(other_contacts.begin(), other_contacts.end(), s) == other_contacts.end())
              other_contacts.push_back(s);
          }
        } else if (std::find(puck_geom.begin(), puck_geom.end(), other) != puck_geom.end()) {
          pc = true;
          if (std::find(puck_contact_geoms.begin(), puck_contact_geoms.end(), ag) == puck_contact_geoms.end())
            puck_contact_geoms.push_back(ag);
        } else {
          std::string s = GName(ag) + "-" + GName(other);
          if (std::find(other_contacts.begin(), other_contacts.end(), s) == other_contacts.end())
            other_contacts.push_back(s);
        }
      }
      table_contact_substeps += tc;
      puck_contact_substeps += pc;
    }
    table_force_sum /= 50;
    for (int i = 0; i < 3; ++i) stale_pos[i] = d->xpos[3 * hand_body + i];
    for (int i = 0; i < 4; ++i) stale_quat[i] = d->xquat[4 * hand_body + i];
    have_stale = true;
    // objects' xyz into the object box (ours: xy only); the reference calls forward if it clipped
    for (size_t i = 0; i < pucks.size(); ++i) {
      double* q = d->qpos + puck_qpos[i];
      if (q[0] < -5) continue;  // parked
      const double o[3] = {q[0], q[1], q[2]};
      q[0] = std::clamp(q[0], -0.24, 0.24);
      q[1] = std::clamp(q[1], 0.37, 0.75);
      if (ref) q[2] = std::clamp(q[2], 0.0, 0.5);
      if (o[0] != q[0] || o[1] != q[1] || o[2] != q[2]) have_stale = false;
    }
    mj_forward(m, d);  // for the measurements (pure: the next mj_step recomputes it)
  }

  // footprint at puck height: union xy AABB of the hand geoms that can touch a puck and whose
  // z range overlaps [zlo, zhi]
  Box3 Footprint(double zlo, double zhi, std::string* which, double* min_z) const {
    Box3 u = {{1e9, 1e9, 1e9}, {-1e9, -1e9, -1e9}};
    *min_z = 1e9;
    which->clear();
    for (int g : hand_geoms) {
      const Box3 b = GeomAabb(m, d, g);
      *min_z = std::min(*min_z, b.lo[2]);
      if (!CanCollide(m, g, puck_geom[0])) continue;
      if (b.hi[2] < zlo || b.lo[2] > zhi) continue;
      for (int i = 0; i < 3; ++i) u.lo[i] = std::min(u.lo[i], b.lo[i]), u.hi[i] = std::max(u.hi[i], b.hi[i]);
      *which += (which->empty() ? "" : ",") + GName(g);
    }
    return u;
  }

  // drive the hand to (x, y) with proportional actions, then settle with zero action
  void GoTo(double x, double y, int settle = 5) {
    for (int k = 0; k < 40; ++k) {
      const double dx = x - HandPos()[0], dy = y - HandPos()[1];
      if (std::hypot(dx, dy) < 0.002) break;
      Step(dx / 0.1, dy / 0.1);
    }
    for (int k = 0; k < settle; ++k) Step(0, 0);
  }
};

static void DescribeGeoms(Env& e) {
  std::printf("\n== %s: collidable geoms of the hand (rigidly attached to '%s') ==\n", e.name.c_str(),
              mj_id2name(e.m, mjOBJ_BODY, e.hand_body));
  const double* hp = e.HandPos();
  for (int g : e.hand_geoms) {
    const Box3 b = GeomAabb(e.m, e.d, g);
    std::printf("  %-14s type %d contype %3d conaff %3d puck:%s table:%s  x[%+.3f,%+.3f] y[%+.3f,%+.3f] z[%+.3f,%+.3f] (rel. hand)\n",
                e.GName(g).c_str(), e.m->geom_type[g], e.m->geom_contype[g], e.m->geom_conaffinity[g],
                CanCollide(e.m, g, e.puck_geom[0]) ? "y" : "n", CanCollide(e.m, g, e.table) ? "y" : "n",
                b.lo[0] - hp[0], b.hi[0] - hp[0], b.lo[1] - hp[1], b.hi[1] - hp[1], b.lo[2], b.hi[2]);
  }
  double mass = 0;
  for (int b = 1; b < e.m->nbody; ++b)
    if (e.m->body_weldid[b] == e.m->body_weldid[e.hand_body]) mass += e.m->body_mass[b];
  std::printf("  mass of the rigid end-effector: %.4f kg; other moving collidable arm geoms: %zu\n", mass,
              e.arm_geoms.size() - e.hand_geoms.size());
}

// E1: free motion under a constant full action
static void FreeRun(Env& e, double sx, double sy, double ax, double ay, int steps, bool from_reset) {
  e.Reset();
  if (!from_reset) e.GoTo(sx, sy);
  std::printf("\n== %s: a=(%g,%g) from (%.3f,%.3f)%s ==\n", e.name.c_str(), ax, ay, e.HandPos()[0], e.HandPos()[1],
              from_reset ? " [reset pose]" : "");
  std::printf(" step   hand_x  hand_y  hand_z | d/step  peak_v | lag_xy  mocap_z | minz_geoms | table: substeps force pen | footprint@puck(z 0..0.03) x-width y-depth [geoms] | other contacts\n");
  double px = e.HandPos()[0], py = e.HandPos()[1];
  for (int s = 1; s <= steps; ++s) {
    e.Step(ax, ay);
    const double* h = e.HandPos();
    const double* mp = e.d->mocap_pos + 3 * e.mocap;
    std::string which;
    double minz;
    const Box3 f = e.Footprint(0.0, 0.03, &which, &minz);
    std::string oc;
    for (auto& s2 : e.other_contacts) oc += s2 + " ";
    std::printf(" %3d  %+.4f %.4f %.4f | %.4f %.3f | %.4f %.4f | %+.4f | %2d %6.2f %.4f | %.3f %.3f [%s] | %s\n", s, h[0],
                h[1], h[2], std::hypot(h[0] - px, h[1] - py), e.peak_speed, std::hypot(mp[0] - h[0], mp[1] - h[1]),
                mp[2], minz, e.table_contact_substeps, e.table_force_sum, e.max_table_pen,
                which.empty() ? 0.0 : f.hi[0] - f.lo[0], which.empty() ? 0.0 : f.hi[1] - f.lo[1], which.c_str(),
                oc.c_str());
    px = h[0], py = h[1];
  }
}

// E2: head-on push under a constant full action
static void Push(Env& e, double puck_y, int steps) {
  e.Reset();
  e.GoTo(0.0, 0.42);
  e.SetPuck(0, 0.0, puck_y);
  mj_forward(e.m, e.d);
  e.Step(0, 0);
  e.Step(0, 0);
  std::printf("\n== %s: head-on push, a=(0,1), hand from (%.3f,%.3f), puck at (0,%.3f) ==\n", e.name.c_str(),
              e.HandPos()[0], e.HandPos()[1], e.PuckPos(0)[1]);
  std::printf(" step  hand_y  puck_x  puck_y  puck_z | hand d/step puck d/step | puck contact substeps [geoms]\n");
  double hy = e.HandPos()[1], qx = e.PuckPos(0)[0], qy = e.PuckPos(0)[1];
  for (int s = 1; s <= steps; ++s) {
    e.Step(0, 1);
    std::string g;
    for (int x : e.puck_contact_geoms) g += e.GName(x) + " ";
    const double* p = e.PuckPos(0);
    std::printf(" %3d  %.4f %+.4f %.4f %.4f | %.4f %.4f | %2d [%s]\n", s, e.HandPos()[1], p[0], p[1], p[2],
                e.HandPos()[1] - hy, std::hypot(p[0] - qx, p[1] - qy), e.puck_contact_substeps, g.c_str());
    hy = e.HandPos()[1], qx = p[0], qy = p[1];
  }
}

// E3: hit and stop: full action until the hand touches the puck, then zero action.
// Returns the puck's total displacement after 10 more steps.
static double HitAndStop(Env& e, double dir_x, double dir_y, double puck_dist, double lateral, bool verbose,
                         double* during, double* after_stop) {
  e.Reset();
  // start in the middle of the table, away from the walls
  const double sx = dir_x != 0 ? -0.15 * dir_x : 0.0, sy = dir_y != 0 ? 0.45 : 0.55;
  e.GoTo(sx, sy);
  const double px = e.HandPos()[0] + dir_x * puck_dist - dir_y * lateral;
  const double py = e.HandPos()[1] + dir_y * puck_dist + dir_x * lateral;
  e.SetPuck(0, px, py);
  mj_forward(e.m, e.d);
  e.Step(0, 0);
  const double x0 = e.PuckPos(0)[0], y0 = e.PuckPos(0)[1];
  int hit = -1;
  for (int s = 0; s < 8; ++s) {
    e.Step(dir_x, dir_y);
    if (e.puck_contact_substeps > 0) {
      hit = s;
      break;
    }
  }
  const double xh = e.PuckPos(0)[0], yh = e.PuckPos(0)[1];
  for (int s = 0; s < 10; ++s) e.Step(0, 0);
  const double* p = e.PuckPos(0);
  const double tot = std::hypot(p[0] - x0, p[1] - y0);
  *during = std::hypot(xh - x0, yh - y0);
  *after_stop = std::hypot(p[0] - xh, p[1] - yh);
  if (verbose)
    std::printf("   dist %.3f lateral %+.3f: hit in step %d, puck moved %.4f in the hit step, %.4f after the stop, total %.4f\n",
                puck_dist, lateral, hit + 1, *during, *after_stop, tot);
  return hit < 0 ? 0.0 : tot;
}

// E4: a pass at full action past a puck offset laterally; puck displacement vs offset
static double Pass(Env& e, double dir_x, double dir_y, double lateral, int steps) {
  e.Reset();
  const double sx = dir_x != 0 ? -0.18 * dir_x : 0.0, sy = dir_y != 0 ? 0.42 : 0.55;
  e.GoTo(sx, sy);
  const double px = dir_x != 0 ? 0.0 : sx - lateral;
  const double py = dir_y != 0 ? 0.58 : sy + lateral;
  e.SetPuck(0, px, py);
  mj_forward(e.m, e.d);
  e.Step(0, 0);
  const double x0 = e.PuckPos(0)[0], y0 = e.PuckPos(0)[1];
  for (int s = 0; s < steps; ++s) e.Step(dir_x, dir_y);
  for (int s = 0; s < 5; ++s) e.Step(0, 0);
  return std::hypot(e.PuckPos(0)[0] - x0, e.PuckPos(0)[1] - y0);
}

int main() {
  Env ref, refnb, ours;
  ref.Init("REFERENCE", kRefXml, true);
  // sensitivity variant: without the persistent contact between the shoulder link's collision
  // sphere (right_l0) and the base cylinder (right_arm_base_link), which brakes joint j0
  ours.Init("OURS", kOursXml, false);
  refnb.Init("REFERENCE-no-l0-base-contact", kRefXml, true);
  for (int g = 0; g < refnb.m->ngeom; ++g)
    if (refnb.m->geom_bodyid[g] == mj_name2id(refnb.m, mjOBJ_BODY, "right_l0") && refnb.m->geom_contype[g])
      refnb.m->geom_contype[g] = refnb.m->geom_conaffinity[g] = 0;
  refnb.arm_geoms.erase(std::remove_if(refnb.arm_geoms.begin(), refnb.arm_geoms.end(), [&](int g) {
    return !(refnb.m->geom_contype[g] || refnb.m->geom_conaffinity[g]); }), refnb.arm_geoms.end());
  for (Env* e : {&ref, &refnb, &ours}) {
    e->Reset();
    DescribeGeoms(*e);
    std::printf("  reset hand pos %.4f %.4f %.4f\n", e->HandPos()[0], e->HandPos()[1], e->HandPos()[2]);
  }
  for (Env* e : {&ref, &refnb, &ours}) {
    e->Reset();
    std::printf("\n== %s: zero action from reset ==\n", e->name.c_str());
    for (int s = 1; s <= 10; ++s) {
      e->Step(0, 0);
      if (s <= 3 || s == 10)
        std::printf("  step %d hand %.4f %.4f %.4f\n", s, e->HandPos()[0], e->HandPos()[1], e->HandPos()[2]);
    }
  }
  // settled hand height over the workspace
  for (Env* e : {&ref, &refnb, &ours}) {
    std::printf("\n== %s: settled hand after GoTo(x, y): xy error (mm) / finger-or-box bottom z (mm) / touches pucks (bottom < 30 mm) ==\n", e->name.c_str());
    std::printf("   y\\x ");
    for (double x = -0.2; x < 0.21; x += 0.05) std::printf("   %+.2f       ", x);
    std::printf("\n");
    for (double y = 0.40; y < 0.76; y += 0.05) {
      std::printf("  %.2f ", y);
      for (double x = -0.2; x < 0.21; x += 0.05) {
        e->Reset();
        e->GoTo(x, y, 5);
        std::string which;
        double minz;
        e->Footprint(0.0, 0.03, &which, &minz);
        std::printf(" %5.1f/%5.1f %s  ", 1000 * std::hypot(e->HandPos()[0] - x, e->HandPos()[1] - y), 1000 * minz,
                    which.empty() ? "--" : "ok");
      }
      std::printf("\n");
    }
  }
  for (Env* e : {&ref, &refnb, &ours}) {
    FreeRun(*e, 0, 0.4, 0, 1, 20, true);
    FreeRun(*e, -0.15, 0.55, 1, 0, 12, false);
    FreeRun(*e, 0.15, 0.55, -1, 0, 6, false);
    FreeRun(*e, 0.0, 0.70, 0, -1, 6, false);
    FreeRun(*e, -0.15, 0.55, 0.3, 0, 6, false);
  }
  for (Env* e : {&ref, &refnb, &ours}) Push(*e, 0.60, 12);

  for (Env* e : {&ref, &refnb, &ours}) {
    for (int dir = 0; dir < 2; ++dir) {
      const double dx = dir == 0 ? 1 : 0, dy = dir == 0 ? 0 : 1;
      std::printf("\n== %s: hit and stop along %s (puck centre 0.10..0.19 ahead, head-on) ==\n", e->name.c_str(),
                  dir == 0 ? "+x" : "+y");
      double sum = 0, mx = 0, sd = 0, sa = 0;
      int n = 0;
      for (double dist = 0.10; dist < 0.195; dist += 0.01) {
        double du, af;
        const double t = HitAndStop(*e, dx, dy, dist, 0.0, true, &du, &af);
        sum += t, mx = std::max(mx, t), sd += du, sa += af, ++n;
      }
      std::printf("  mean total %.4f (in the hit step %.4f, after the stop %.4f), max %.4f\n", sum / n, sd / n, sa / n,
                  mx);
    }
  }
  for (Env* e : {&ref, &refnb, &ours}) {
    for (int dir = 0; dir < 2; ++dir) {
      const double dx = dir == 0 ? 1 : 0, dy = dir == 0 ? 0 : 1;
      std::printf("\n== %s: full-speed pass along %s, puck offset sideways (lateral = %s) ==\n", e->name.c_str(),
                  dir == 0 ? "+x" : "+y", dir == 0 ? "puck y - hand y" : "hand x - puck x");
      std::printf("  lateral: displacement\n");
      double lo1 = 1, hi1 = -1, lo5 = 1, hi5 = -1;
      for (int k = -32; k <= 32; ++k) {
        const double lat = 0.0025 * k;
        const double disp = Pass(*e, dx, dy, lat, 4);
        if (std::fabs(lat) > 0.035) std::printf("  %+.4f: %.4f\n", lat, disp);
        if (disp > 0.01) lo1 = std::min(lo1, lat), hi1 = std::max(hi1, lat);
        if (disp > 0.05) lo5 = std::min(lo5, lat), hi5 = std::max(hi5, lat);
      }
      std::printf("  offsets moved > 1 cm: [%+.4f, %+.4f] (width %.4f); moved > 5 cm: [%+.4f, %+.4f] (width %.4f)\n", lo1, hi1, hi1 - lo1, lo5, hi5, hi5 - lo5);
    }
  }
  return 0;
}
