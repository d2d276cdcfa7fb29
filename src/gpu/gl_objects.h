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

// One new GL name from `generate` (glGenTextures, glGenBuffers, ...), owned.
template <class Name, class Generate>
Name genName(Generate generate) {
  GLuint id = 0;
  generate(1, &id);
  return Name(id);
}
inline GlTexture genTexture() {
  return genName<GlTexture>(glGenTextures);
}
inline GlBuffer genBuffer() {
  return genName<GlBuffer>(glGenBuffers);
}
inline GlFramebuffer genFramebuffer() {
  return genName<GlFramebuffer>(glGenFramebuffers);
}
inline GlVertexArray genVertexArray() {
  return genName<GlVertexArray>(glGenVertexArrays);
}

// An immutable single-level 2D texture of `internalFormat`, nearest filtering, clamped.
GlTexture makeTexture2D(GLenum internalFormat, int width, int height);

}  // namespace pluvia::gpu
