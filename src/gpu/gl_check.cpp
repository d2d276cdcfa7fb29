#include "gpu/gl_check.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include "gpu/rain_error.h"

namespace pluvia::gpu {
namespace {

const char* glErrorName(GLenum error) {
  struct Named {
    GLenum code;
    const char* name;
  };
  static constexpr Named kErrors[] = {
      {GL_INVALID_ENUM, "GL_INVALID_ENUM"},
      {GL_INVALID_VALUE, "GL_INVALID_VALUE"},
      {GL_INVALID_OPERATION, "GL_INVALID_OPERATION"},
      {GL_INVALID_FRAMEBUFFER_OPERATION, "GL_INVALID_FRAMEBUFFER_OPERATION"},
      {GL_OUT_OF_MEMORY, "GL_OUT_OF_MEMORY"},
      {GL_STACK_OVERFLOW, "GL_STACK_OVERFLOW"},
      {GL_STACK_UNDERFLOW, "GL_STACK_UNDERFLOW"},
  };
  for (const Named& known : kErrors) {
    if (known.code == error) return known.name;
  }
  return "unknown GL error";
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
