#pragma once
// The streaks of a frame on the GPU: a shader storage buffer of StreakInstance that
// shaders/rain_stroke.vert pulls from, drawn as one wide line per streak (streak
// gl_VertexID / 2, end gl_VertexID % 2) or as two triangles per streak through a static index
// buffer (streak gl_VertexID / 4, corner gl_VertexID % 4); see streak_batches.h for which. No
// instancing: llvmpipe runs its vertex pipeline once per instance, a fixed cost per streak
// that one draw per batch avoids.
#include <vector>

#include "gpu/gl_objects.h"
#include "rain/streak_types.h"

namespace pluvia::gpu {

class StreakStream {
 public:
  StreakStream();

  // Copies the streaks to the GPU. The buffers are reallocated only when the count outgrows
  // them, so a long clip settles on one allocation.
  void upload(const std::vector<rain::StreakInstance>& streaks);
  // Binds the streak buffer to storage binding `binding` for the draws below.
  void bind(GLuint binding) const;
  // Streaks [first, first + count) of the upload as lines `widthPx` wide, or as triangles;
  // the vertex shader must be in the matching mode (RainProgram::setLines).
  void drawLines(size_t first, size_t count, float widthPx) const;
  void drawTriangles(size_t first, size_t count) const;
  // The widest line the device draws (GL_ALIASED_LINE_WIDTH_RANGE).
  float maxLineWidthPx() const { return maxLineWidthPx_; }

 private:
  GlVertexArray vertexArray_;  // no attributes: the core profile still needs one bound
  GlBuffer streaks_;
  GlBuffer indices_;
  size_t capacity_ = 0;  // streaks
  float maxLineWidthPx_ = 1.0f;
};

}  // namespace pluvia::gpu
