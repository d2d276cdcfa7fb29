#pragma once
// The streaks of a frame on the GPU: a shader storage buffer of StreakInstance that
// shaders/rain_stroke.vert pulls from (streak gl_VertexID / 4, corner gl_VertexID % 4), and a
// static index buffer of two triangles per streak. No instancing: llvmpipe runs its vertex
// pipeline once per instance, a fixed cost per streak that one indexed draw avoids.
#include <vector>

#include "gpu/gl_objects.h"
#include "gpu/rain_renderer.h"

namespace pluvia::gpu {

class StreakStream {
 public:
  StreakStream();

  // Copies the streaks to the GPU. The buffers are reallocated only when the count outgrows
  // them, so a long clip settles on one allocation.
  void upload(const std::vector<StreakInstance>& streaks);
  // Binds the streak buffer to storage binding `binding` and draws two triangles per uploaded
  // streak, in order.
  void draw(GLuint binding) const;

 private:
  GlVertexArray vertexArray_;  // no attributes: the core profile still needs one bound
  GlBuffer streaks_;
  GlBuffer indices_;
  size_t capacity_ = 0;  // streaks
  size_t count_ = 0;
};

}  // namespace pluvia::gpu
