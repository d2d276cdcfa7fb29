#pragma once
// Move-only owners of GL object names: each deletes its object when it goes, so a renderer
// that is destroyed (or re-sized) leaks nothing. The owning context must be current then.
#include <utility>

#include <epoxy/gl.h>

namespace pluvia::gpu {
namespace gl_delete {
inline void texture(GLuint id) {
  glDeleteTextures(1, &id);
}
inline void buffer(GLuint id) {
  glDeleteBuffers(1, &id);
}
inline void framebuffer(GLuint id) {
  glDeleteFramebuffers(1, &id);
}
inline void vertexArray(GLuint id) {
  glDeleteVertexArrays(1, &id);
}
inline void program(GLuint id) {
  glDeleteProgram(id);
}
inline void shader(GLuint id) {
  glDeleteShader(id);
}
}  // namespace gl_delete

template <void (*Delete)(GLuint)>
class GlName {
 public:
  GlName() = default;
  explicit GlName(GLuint id) : id_(id) {}
  ~GlName() { reset(); }
  GlName(GlName&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  GlName& operator=(GlName&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  GlName(const GlName&) = delete;
  GlName& operator=(const GlName&) = delete;

  GLuint id() const { return id_; }
  void reset() {
    if (id_ != 0) Delete(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

using GlTexture = GlName<gl_delete::texture>;
using GlBuffer = GlName<gl_delete::buffer>;
using GlFramebuffer = GlName<gl_delete::framebuffer>;
using GlVertexArray = GlName<gl_delete::vertexArray>;
using GlProgram = GlName<gl_delete::program>;
using GlShader = GlName<gl_delete::shader>;

inline GlTexture genTexture() {
  GLuint id = 0;
  glGenTextures(1, &id);
  return GlTexture(id);
}
inline GlBuffer genBuffer() {
  GLuint id = 0;
  glGenBuffers(1, &id);
  return GlBuffer(id);
}
inline GlFramebuffer genFramebuffer() {
  GLuint id = 0;
  glGenFramebuffers(1, &id);
  return GlFramebuffer(id);
}
inline GlVertexArray genVertexArray() {
  GLuint id = 0;
  glGenVertexArrays(1, &id);
  return GlVertexArray(id);
}

// An immutable single-level 2D texture of `internalFormat`, nearest filtering, clamped.
GlTexture makeTexture2D(GLenum internalFormat, int width, int height);

}  // namespace pluvia::gpu
