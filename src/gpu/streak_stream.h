#pragma once
// The streaks of a frame as an instanced vertex buffer (one StreakInstance per instance) and
// the vertex array that feeds them to shaders/rain_stroke.vert.
#include <vector>

#include "gpu/gl_objects.h"
#include "gpu/rain_renderer.h"

namespace pluvia::gpu {

class StreakStream {
 public:
  StreakStream();

  // Copies the streaks to the GPU. The buffer is reallocated only when the count outgrows it,
  // so a long clip settles on one allocation.
  void upload(const std::vector<StreakInstance>& streaks);
  // Draws one 4-vertex triangle strip per uploaded streak, in order.
  void draw() const;

 private:
  GlVertexArray vertexArray_;
  GlBuffer buffer_;
  size_t capacity_ = 0;  // streaks
  size_t count_ = 0;
};

}  // namespace pluvia::gpu
