#pragma once
// MuJoCo plumbing: error handlers that throw, RAII owners, loading MJCF text from memory.
// Internal to actor/env (and its tests and benchmark): the interface in environment.h has no
// MuJoCo in it.

#include <mujoco/mujoco.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace srics::env {

// Any MuJoCo error: a fatal engine error or an MJCF that does not compile. The message is
// MuJoCo's own.
class MujocoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Installs (once per process) an mju_user_error that throws MujocoError instead of waiting
// for a key press and exiting, and an mju_user_warning that prints the first warnings to
// stderr (warnings such as bad accelerations are also counted in mjData and checked by the
// environment). Called by every loader below; call it before any other MuJoCo use.
void InstallMujocoHandlers();

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// Compiles MJCF text through a virtual file system (no file is written). Throws MujocoError
// "MJCF error: <MuJoCo's message>" when it does not compile.
ModelPtr LoadModelFromXml(const std::string& xml);

// A fresh mjData for `model` (throws MujocoError when MuJoCo cannot allocate it).
DataPtr MakeData(const mjModel* model);

// True when MuJoCo flagged (and reset) a numerical blow-up since the counters were cleared:
// bad qpos, qvel or qacc.
inline bool HasInstabilityWarning(const mjData* d) {
  return d->warning[mjWARN_BADQACC].number > 0 || d->warning[mjWARN_BADQVEL].number > 0 ||
         d->warning[mjWARN_BADQPOS].number > 0;
}

}  // namespace srics::env
