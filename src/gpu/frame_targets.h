#pragma once
// The GPU images of one frame size: the scene depth (sampled by the fragment shader) and the
// rain layer (the colour attachment of one framebuffer). Made once per size and reused frame
// after frame. The background never goes to the GPU: render() composites on the read-back
// layer (rain_renderer.h).
#include <vector>

#include "gpu/gl_objects.h"

namespace pluvia::gpu {

class FrameTargets {
 public:
  FrameTargets(int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }

  // Uploads the scene depth (metres, finite; skipped when null: the shader variant without a
  // depth plane reads none) and sets the rain layer to transparent black. Leaves the
  // framebuffer bound for drawing.
  void begin(const std::vector<float>* depthMeters);
  void bindSceneDepth(GLuint depthUnit) const;
  // Row 0 of the output is row 0 of the image (its top): nothing is flipped anywhere.
  void readRainLayer(float* rgba) const;

 private:
  int width_;
  int height_;
  GlTexture depth_;
  GlTexture rain_;
  GlFramebuffer framebuffer_;
};

}  // namespace pluvia::gpu
