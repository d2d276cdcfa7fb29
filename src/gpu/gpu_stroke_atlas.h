#pragma once
// The stroke atlas on the GPU: the mattes as an R32F texture (GL_LINEAR, CLAMP_TO_EDGE, as
// renderRainCpu samples them) and the per-stroke rectangles as a shader storage buffer.
#include "gpu/gl_objects.h"
#include "rain/streak_types.h"

namespace pluvia::gpu {

class GpuStrokeAtlas {
 public:
  // Replaces the atlas; the texture is re-made only when the atlas size changes.
  void upload(const rain::StrokeAtlas& atlas);
  void bind(GLuint textureUnit, GLuint rectBinding) const;

  int strokeCount() const { return strokeCount_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  GlTexture texture_;
  GlBuffer rects_;
  int width_ = 0;
  int height_ = 0;
  int strokeCount_ = 0;
};

}  // namespace pluvia::gpu
