#include "actor/env/mujoco_util.h"

#include <atomic>
#include <cstdio>
#include <cstring>
#include <mutex>

namespace srics::env {
namespace {

constexpr int kMaxPrintedWarnings = 20;
std::atomic<int> printed_warnings{0};

[[noreturn]] void ThrowOnError(const char* message) { throw MujocoError(message); }

void PrintWarning(const char* message) {
  // rate-limited: a blow-up in many envs must not flood the log
  if (printed_warnings.fetch_add(1) < kMaxPrintedWarnings) std::fprintf(stderr, "MuJoCo warning: %s\n", message);
}

// The VFS is 2 MB of file names: keep it on the heap, and free its files on every path.
struct VfsDeleter {
  void operator()(mjVFS* vfs) const {
    mj_deleteVFS(vfs);
    delete vfs;
  }
};

}  // namespace

void InstallMujocoHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = ThrowOnError;
    mju_user_warning = PrintWarning;
  });
}

ModelPtr LoadModelFromXml(const std::string& xml) {
  InstallMujocoHandlers();
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  const char* name = "model.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0)
    throw MujocoError("MJCF error: cannot create the in-memory file");
  const int index = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[index], xml.data(), xml.size());
  char error[1024] = "";
  mjModel* model = mj_loadXML(name, vfs.get(), error, sizeof(error));
  if (model == nullptr) throw MujocoError(std::string("MJCF error: ") + error);
  return ModelPtr(model);
}

DataPtr MakeData(const mjModel* model) {
  InstallMujocoHandlers();
  mjData* data = mj_makeData(model);
  if (data == nullptr) throw MujocoError("mj_makeData failed");
  return DataPtr(data);
}

}  // namespace srics::env
