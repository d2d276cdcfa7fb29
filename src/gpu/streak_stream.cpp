#include "gpu/streak_stream.h"

#include <cstddef>

#include "gpu/gl_check.h"

namespace pluvia::gpu {
namespace {

// Attribute locations of shaders/rain_stroke.vert and where each starts in a StreakInstance.
struct InstanceAttribute {
  GLuint location;
  GLint components;
  size_t offset;
};
constexpr InstanceAttribute kAttributes[] = {
    {0, 4, offsetof(StreakInstance, headX)},    // head, tail
    {1, 4, offsetof(StreakInstance, widthPx)},  // width, alpha, depth, stroke index
    {2, 3, offsetof(StreakInstance, viewX)},    // view direction
};

}  // namespace

StreakStream::StreakStream() : vertexArray_(genVertexArray()), buffer_(genBuffer()) {
  glBindVertexArray(vertexArray_.id());
  glBindBuffer(GL_ARRAY_BUFFER, buffer_.id());
  for (const InstanceAttribute& attribute : kAttributes) {
    glEnableVertexAttribArray(attribute.location);
    glVertexAttribPointer(attribute.location, attribute.components, GL_FLOAT, GL_FALSE,
                          sizeof(StreakInstance), reinterpret_cast<const void*>(attribute.offset));
    glVertexAttribDivisor(attribute.location, 1);
  }
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  checkGl("setting up the streak vertex array");
}

void StreakStream::upload(const std::vector<StreakInstance>& streaks) {
  glBindBuffer(GL_ARRAY_BUFFER, buffer_.id());
  const auto bytes = static_cast<GLsizeiptr>(streaks.size() * sizeof(StreakInstance));
  if (streaks.size() > capacity_) {
    glBufferData(GL_ARRAY_BUFFER, bytes, streaks.data(), GL_STREAM_DRAW);
    capacity_ = streaks.size();
  } else {
    glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, streaks.data());
  }
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  count_ = streaks.size();
  checkGl("uploading the streaks");
}

void StreakStream::draw() const {
  glBindVertexArray(vertexArray_.id());
  glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(count_));
  glBindVertexArray(0);
  checkGl("drawing the streaks");
}

}  // namespace pluvia::gpu
