#include "gpu/gl_check.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include "gpu/rain_error.h"

namespace pluvia::gpu {
namespace {

const char* glErrorName(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    default: return "unknown GL error";
  }
}

}  // namespace

void checkGl(std::string_view step) {
  std::string errors;
  // Several error flags can be pending; glGetError returns and clears one at a time. The
  // bound keeps a lost context (which may report errors forever) from looping.
  for (int i = 0; i < 16; ++i) {
    const GLenum error = glGetError();
    if (error == GL_NO_ERROR) break;
    errors += fmt::format("{}{} (0x{:04x})", errors.empty() ? "" : ", ", glErrorName(error), error);
  }
  if (!errors.empty()) throwRainError(fmt::format("OpenGL error while {}: {}", step, errors));
}

}  // namespace pluvia::gpu
