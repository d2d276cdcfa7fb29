#include "gpu/streak_stream.h"

#include <cstdint>

#include <fmt/format.h>

#include "gpu/gl_check.h"
#include "gpu/rain_error.h"

namespace pluvia::gpu {

StreakStream::StreakStream()
    : vertexArray_(genVertexArray()), streaks_(genBuffer()), indices_(genBuffer()) {
  GLfloat range[2] = {1.0f, 1.0f};
  glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, range);
  maxLineWidthPx_ = range[1];
  checkGl("querying the line width range");
}

void StreakStream::upload(const std::vector<rain::StreakInstance>& streaks) {
  const auto bytes = static_cast<GLsizeiptr>(streaks.size() * sizeof(rain::StreakInstance));
  GLint64 maxBytes = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBytes);
  if (bytes > maxBytes) {
    throwRainError(fmt::format("{} streaks need {} bytes, more than the GPU's {} per draw",
                               streaks.size(), bytes, maxBytes));
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, streaks_.id());
  if (streaks.size() > capacity_) {
    glBufferData(GL_SHADER_STORAGE_BUFFER, bytes, streaks.data(), GL_STREAM_DRAW);
    // Corners 0 1 2 3 are (left, head), (right, head), (left, tail), (right, tail): the
    // triangles (0, 1, 2) and (2, 1, 3), the two of a 4-vertex strip.
    std::vector<uint32_t> indices(streaks.size() * 6);
    for (size_t i = 0; i < streaks.size(); ++i) {
      const auto base = static_cast<uint32_t>(4 * i);
      const uint32_t quad[6] = {base, base + 1, base + 2, base + 2, base + 1, base + 3};
      std::copy(quad, quad + 6, indices.begin() + static_cast<std::ptrdiff_t>(6 * i));
    }
    glBindVertexArray(vertexArray_.id());
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_.id());
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(indices.size() * sizeof(uint32_t)), indices.data(),
                 GL_STATIC_DRAW);
    glBindVertexArray(0);
    capacity_ = streaks.size();
  } else {
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, bytes, streaks.data());
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  checkGl("uploading the streaks");
}

void StreakStream::bind(GLuint binding) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, streaks_.id());
  glBindVertexArray(vertexArray_.id());
}

void StreakStream::drawLines(size_t first, size_t count, float widthPx) const {
  glLineWidth(widthPx);
  glDrawArrays(GL_LINES, static_cast<GLint>(2 * first), static_cast<GLsizei>(2 * count));
  checkGl(fmt::format("drawing {} streaks as lines {} px wide", count, widthPx));
}

void StreakStream::drawTriangles(size_t first, size_t count) const {
  const auto offset = static_cast<uintptr_t>(6 * first * sizeof(uint32_t));
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(6 * count), GL_UNSIGNED_INT,
                 reinterpret_cast<const void*>(offset));
  checkGl(fmt::format("drawing {} streaks as triangles", count));
}

}  // namespace pluvia::gpu
