#include "actor/env/render/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <vector>

namespace srics::env {
namespace {

constexpr unsigned kGlRenderer = 0x1F01;  // GL_RENDERER (no GL header needed for one enum)

std::string EglErrorText() {
  char text[32];
  std::snprintf(text, sizeof(text), "EGL error 0x%04x", static_cast<unsigned>(eglGetError()));
  return text;
}

}  // namespace

struct GlContext::Egl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;

  ~Egl() {
    if (display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    eglTerminate(display);
  }

  // Initialises `candidate` and makes an OpenGL context current on it; "" on success, else
  // what failed (and nothing is kept).
  std::string Open(EGLDisplay candidate) {
    if (candidate == EGL_NO_DISPLAY) return "no display (" + EglErrorText() + ")";
    EGLint major = 0, minor = 0;
    if (!eglInitialize(candidate, &major, &minor)) return "eglInitialize failed (" + EglErrorText() + ")";
    // no surface: MuJoCo renders into its own offscreen framebuffer object
    const EGLint config_attributes[] = {
        EGL_RED_SIZE,   8,       EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_DEPTH_SIZE, 24, EGL_RENDERABLE_TYPE,
        EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    const bool chose = eglChooseConfig(candidate, config_attributes, &config, 1, &configs) && configs > 0;
    std::string problem;
    if (!eglBindAPI(EGL_OPENGL_API)) {
      problem = "no desktop OpenGL (" + EglErrorText() + ")";
    } else {
      // Mesa creates contexts without a config (EGL_KHR_no_config_context) when none fits
      const EGLContext made = eglCreateContext(candidate, chose ? config : nullptr, EGL_NO_CONTEXT, nullptr);
      if (made == EGL_NO_CONTEXT) {
        problem = "eglCreateContext failed (" + EglErrorText() + ")";
      } else if (!eglMakeCurrent(candidate, EGL_NO_SURFACE, EGL_NO_SURFACE, made)) {
        problem = "eglMakeCurrent without a surface failed (" + EglErrorText() + ")";
        eglDestroyContext(candidate, made);
      } else {
        display = candidate;
        context = made;
        return "";
      }
    }
    eglTerminate(candidate);
    return problem;
  }
};

GlContext::GlContext() : egl_(std::make_unique<Egl>()) {
  const auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  const auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  std::string tried;
  std::string platform;

  // a GPU (or Mesa's software device) through EGL_EXT_platform_device
  if (get_platform_display && query_devices) {
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (query_devices(16, devices, &count) && count > 0) {
      for (EGLint i = 0; i < count && platform.empty(); ++i) {
        const std::string problem = egl_->Open(get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr));
        if (problem.empty())
          platform = "device " + std::to_string(i);
        else
          tried += "device " + std::to_string(i) + ": " + problem + "; ";
      }
    } else {
      tried += "devices: none; ";
    }
  }
  // Mesa's surfaceless platform (llvmpipe without any device node)
  if (platform.empty() && get_platform_display) {
    const std::string problem =
        egl_->Open(get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr));
    if (problem.empty())
      platform = "surfaceless";
    else
      tried += "surfaceless: " + problem + "; ";
  }
  if (platform.empty()) {
    const std::string problem = egl_->Open(eglGetDisplay(EGL_DEFAULT_DISPLAY));
    if (problem.empty())
      platform = "default display";
    else
      tried += "default display: " + problem;
  }
  if (platform.empty())
    throw RenderError("no headless OpenGL context through EGL (" + tried +
                      "); Debian: apt-get install libegl-mesa0 libgl1-mesa-dri");

  const char* vendor = eglQueryString(egl_->display, EGL_VENDOR);
  EGLint major = 0, minor = 0;
  eglInitialize(egl_->display, &major, &minor);  // already initialised: returns the version
  description_ =
      "EGL " + std::to_string(major) + "." + std::to_string(minor) + " (" + (vendor ? vendor : "?") + "), " + platform;
  using GetString = const unsigned char* (*)(unsigned);
  if (const auto get_string = reinterpret_cast<GetString>(eglGetProcAddress("glGetString")))
    if (const unsigned char* renderer = get_string(kGlRenderer))
      description_ += ": " + std::string(reinterpret_cast<const char*>(renderer));
}

GlContext::~GlContext() = default;

}  // namespace srics::env
