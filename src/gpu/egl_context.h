#pragma once
// A headless OpenGL (4.5 core, else 4.3 core) context through EGL, with no surface: all
// drawing goes to framebuffer objects. Displays are tried in this order: every device of
// EGL_EXT_platform_device (the right one on NVIDIA), then Mesa's surfaceless platform.
#include <string>

#include <epoxy/egl.h>

namespace pluvia::gpu {

// True when EGL enumerates devices and every one is a software rasteriser (Mesa marks those
// with EGL_MESA_device_software): then a context would draw on the CPU. Asks EGL only, without
// making a display or a context (a fifth of a second).
bool eglDevicesAreAllSoftware();

class HeadlessGlContext {
 public:
  // Creates the context and makes it current on this thread. Throws pluvia::Error naming what
  // failed on each display tried (no display, no config, no context ...).
  HeadlessGlContext();
  ~HeadlessGlContext();
  HeadlessGlContext(const HeadlessGlContext&) = delete;
  HeadlessGlContext& operator=(const HeadlessGlContext&) = delete;

  // Makes the context current on the calling thread unless it already is (another renderer
  // may have made its own context current in between).
  void makeCurrent();

  // Which display the context lives on: "EGL device 0", "Mesa surfaceless".
  const std::string& displayName() const { return displayName_; }
  // "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6 (Mesa surfaceless)":
  // makes the context current and asks GL.
  std::string deviceDescription();

 private:
  bool tryDisplay(EGLDisplay display, const std::string& name, std::string& failure);

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::string displayName_;
};

}  // namespace pluvia::gpu
