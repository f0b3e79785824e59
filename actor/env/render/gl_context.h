#pragma once
// A headless OpenGL context for MuJoCo's offscreen renderer, made through EGL: no display,
// no window. Mesa provides it on any Linux machine (Debian's libegl-mesa0 and
// libgl1-mesa-dri): on a GPU through its device, else in software (llvmpipe) on the
// surfaceless platform.
//
//   GlContext gl;                    // current on this thread until destroyed
//   mjr_makeContext(model, &con, mjFONTSCALE_100);
//
// One thread uses a context; it must outlive every MuJoCo rendering context made in it.

#include <memory>
#include <stdexcept>
#include <string>

namespace srics::env {

// What went wrong while making or using the rendering context (the EGL step and its error).
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class GlContext {
 public:
  // Tries the platforms in order: EGL devices (EGL_EXT_platform_device), then Mesa's
  // surfaceless platform, then the default display; makes the first OpenGL context that
  // works current on this thread. Throws RenderError listing what each platform answered.
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // "EGL 1.5 (Mesa Project), surfaceless: llvmpipe (LLVM 15.0.6, 256 bits)" (for logs).
  const std::string& description() const { return description_; }

 private:
  struct Egl;
  std::unique_ptr<Egl> egl_;
  std::string description_;
};

}  // namespace srics::env
