#pragma once
// The GPU images of one frame size: the background B and the scene depth (sampled by the
// fragment shader), and the composite and the rain layer (colour attachments 0 and 1 of one
// framebuffer). Made once per size and reused frame after frame.
#include <vector>

#include "gpu/gl_objects.h"

namespace pluvia::gpu {

class FrameTargets {
 public:
  FrameTargets(int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }

  // Uploads B (RGBA) and the scene depth (metres, finite), sets the composite to B and the
  // rain layer to transparent black. Leaves the framebuffer bound for drawing.
  void begin(const std::vector<float>& backgroundRgba, const std::vector<float>& depthMeters);
  void bindInputs(GLuint backgroundUnit, GLuint depthUnit) const;
  // Row 0 of the output is row 0 of the image (its top): nothing is flipped anywhere.
  void readComposite(float* rgba) const;
  void readRainLayer(float* rgba) const;

 private:
  void readAttachment(GLenum attachment, float* rgba) const;

  int width_;
  int height_;
  GlTexture background_;
  GlTexture depth_;
  GlTexture composite_;
  GlTexture rain_;
  GlFramebuffer framebuffer_;
};

}  // namespace pluvia::gpu
