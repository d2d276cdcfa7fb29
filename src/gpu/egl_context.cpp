#include "gpu/egl_context.h"

#include <map>
#include <mutex>
#include <vector>

#include <epoxy/gl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "gpu/rain_error.h"

namespace pluvia::gpu {
namespace {

std::string eglErrorName(EGLint error) {
  struct Named {
    EGLint code;
    const char* name;
  };
  static constexpr Named kErrors[] = {
      {EGL_SUCCESS, "EGL_SUCCESS"},
      {EGL_NOT_INITIALIZED, "EGL_NOT_INITIALIZED"},
      {EGL_BAD_ACCESS, "EGL_BAD_ACCESS"},
      {EGL_BAD_ALLOC, "EGL_BAD_ALLOC"},
      {EGL_BAD_ATTRIBUTE, "EGL_BAD_ATTRIBUTE"},
      {EGL_BAD_CONFIG, "EGL_BAD_CONFIG"},
      {EGL_BAD_CONTEXT, "EGL_BAD_CONTEXT"},
      {EGL_BAD_CURRENT_SURFACE, "EGL_BAD_CURRENT_SURFACE"},
      {EGL_BAD_DISPLAY, "EGL_BAD_DISPLAY"},
      {EGL_BAD_MATCH, "EGL_BAD_MATCH"},
      {EGL_BAD_NATIVE_PIXMAP, "EGL_BAD_NATIVE_PIXMAP"},
      {EGL_BAD_NATIVE_WINDOW, "EGL_BAD_NATIVE_WINDOW"},
      {EGL_BAD_PARAMETER, "EGL_BAD_PARAMETER"},
      {EGL_BAD_SURFACE, "EGL_BAD_SURFACE"},
      {EGL_CONTEXT_LOST, "EGL_CONTEXT_LOST"},
  };
  for (const Named& known : kErrors) {
    if (known.code == error) return known.name;
  }
  return fmt::format("EGL error 0x{:04x}", error);
}

std::string lastEglError() {
  return eglErrorName(eglGetError());
}

bool hasExtension(const char* extensions, std::string_view name) {
  if (!extensions) return false;
  std::string_view list(extensions);
  for (size_t start = 0; start < list.size();) {
    size_t end = list.find(' ', start);
    if (end == std::string_view::npos) end = list.size();
    if (list.substr(start, end - start) == name) return true;
    start = end + 1;
  }
  return false;
}

// An EGLDisplay is one per (platform, native display) in the whole process and eglTerminate
// is not reference counted, so two renderers on one display would kill each other's context.
// Count the users and terminate with the last one.
std::mutex displayUsersMutex;
std::map<EGLDisplay, int> displayUsers;

bool acquireDisplay(EGLDisplay display) {
  std::lock_guard lock(displayUsersMutex);
  int& users = displayUsers[display];
  if (users == 0 && !eglInitialize(display, nullptr, nullptr)) {
    displayUsers.erase(display);
    return false;
  }
  ++users;
  return true;
}

void releaseDisplay(EGLDisplay display) {
  std::lock_guard lock(displayUsersMutex);
  auto it = displayUsers.find(display);
  if (it == displayUsers.end()) return;
  if (--it->second == 0) {
    eglTerminate(display);
    displayUsers.erase(it);
  }
}

struct CandidateDisplay {
  EGLDisplay display;
  std::string name;
};

// Every display worth trying, best first; `failures` collects why platforms were skipped.
std::vector<CandidateDisplay> candidateDisplays(std::vector<std::string>& failures) {
  std::vector<CandidateDisplay> candidates;
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!hasExtension(clientExtensions, "EGL_EXT_platform_base")) {
    failures.push_back("no display: EGL lacks EGL_EXT_platform_base (is an EGL driver installed?)");
    return candidates;
  }
  if (hasExtension(clientExtensions, "EGL_EXT_platform_device") &&
      (hasExtension(clientExtensions, "EGL_EXT_device_enumeration") ||
       hasExtension(clientExtensions, "EGL_EXT_device_base"))) {
    EGLint count = 0;
    if (eglQueryDevicesEXT(0, nullptr, &count) && count > 0) {
      std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
      eglQueryDevicesEXT(count, devices.data(), &count);
      for (EGLint i = 0; i < count; ++i) {
        const std::string name = fmt::format("EGL device {}", i);
        EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (display == EGL_NO_DISPLAY) {
          failures.push_back(fmt::format("{}: no display ({})", name, lastEglError()));
        } else {
          candidates.push_back({display, name});
        }
      }
    } else {
      failures.push_back("EGL_EXT_platform_device: no device found");
    }
  }
  if (hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay display =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) {
      failures.push_back(fmt::format("Mesa surfaceless: no display ({})", lastEglError()));
    } else {
      candidates.push_back({display, "Mesa surfaceless"});
    }
  }
  return candidates;
}

}  // namespace

bool eglDevicesAreAllSoftware() {
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!hasExtension(clientExtensions, "EGL_EXT_device_query") ||
      !(hasExtension(clientExtensions, "EGL_EXT_device_enumeration") ||
        hasExtension(clientExtensions, "EGL_EXT_device_base")))
    return false;
  EGLint count = 0;
  if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) return false;
  std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
  if (!eglQueryDevicesEXT(count, devices.data(), &count)) return false;
  for (EGLint i = 0; i < count; ++i) {
    if (!hasExtension(eglQueryDeviceStringEXT(devices[size_t(i)], EGL_EXTENSIONS),
                      "EGL_MESA_device_software"))
      return false;
  }
  return true;
}

HeadlessGlContext::HeadlessGlContext() {
  std::vector<std::string> failures;
  for (const CandidateDisplay& candidate : candidateDisplays(failures)) {
    std::string failure;
    if (tryDisplay(candidate.display, candidate.name, failure)) return;
    failures.push_back(candidate.name + ": " + failure);
  }
  if (failures.empty()) failures.push_back("no display: EGL offers no headless platform");
  throwRainError(fmt::format("cannot create a headless OpenGL 4.3+ context through EGL: {}",
                             fmt::join(failures, "; ")));
}

bool HeadlessGlContext::tryDisplay(EGLDisplay display, const std::string& name,
                                   std::string& failure) {
  if (!acquireDisplay(display)) {
    failure = fmt::format("eglInitialize failed ({})", lastEglError());
    return false;
  }
  // On failure below the display is released again, so a later renderer starts afresh.
  auto fail = [&](const std::string& why) {
    failure = why;
    releaseDisplay(display);
    return false;
  };
  if (!eglBindAPI(EGL_OPENGL_API)) {
    return fail(fmt::format("no desktop OpenGL API ({})", lastEglError()));
  }
  // No surface is ever made, so any surface type will do.
  const EGLint configAttributes[] = {EGL_SURFACE_TYPE, EGL_DONT_CARE, EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configCount = 0;
  const bool chose = eglChooseConfig(display, configAttributes, &config, 1, &configCount);
  if (!chose || configCount < 1) {
    if (!hasExtension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
      return fail(fmt::format("no config for OpenGL ({})",
                              chose ? "none offers EGL_OPENGL_BIT" : lastEglError()));
    }
    config = EGL_NO_CONFIG_KHR;
  }
  for (EGLint minor : {5, 3}) {
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                        4,
                                        EGL_CONTEXT_MINOR_VERSION,
                                        minor,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_NONE};
    context_ = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
    if (context_ != EGL_NO_CONTEXT) break;
  }
  if (context_ == EGL_NO_CONTEXT) {
    return fail(fmt::format("no OpenGL 4.5 or 4.3 core context ({})", lastEglError()));
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
    const std::string error = lastEglError();
    eglDestroyContext(display, context_);
    context_ = EGL_NO_CONTEXT;
    return fail(fmt::format("cannot make the context current without a surface ({})", error));
  }
  display_ = display;
  displayName_ = name;
  return true;
}

HeadlessGlContext::~HeadlessGlContext() {
  if (eglGetCurrentContext() == context_) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  eglDestroyContext(display_, context_);
  releaseDisplay(display_);
}

std::string HeadlessGlContext::deviceDescription() {
  makeCurrent();
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return fmt::format("{}, OpenGL {} ({})", renderer ? renderer : "unknown renderer",
                     version ? version : "unknown version", displayName_);
}

void HeadlessGlContext::makeCurrent() {
  if (eglGetCurrentContext() == context_) return;
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
    throwRainError(
        fmt::format("cannot make the rain renderer's OpenGL context current ({}); "
                    "is it used from another thread?",
                    lastEglError()));
  }
}

}  // namespace pluvia::gpu
