#pragma once
// shaders/rain_stroke.vert + .frag, linked once, with its uniforms and blend state.
#include "gpu/gl_objects.h"
#include "gpu/rain_renderer.h"

namespace pluvia::gpu {

// Texture units and the storage binding the shaders declare (layout(binding = ...)).
inline constexpr GLuint kAtlasUnit = 0;
inline constexpr GLuint kBackgroundUnit = 1;
inline constexpr GLuint kSceneDepthUnit = 2;
inline constexpr GLuint kRadianceMapUnit = 3;
inline constexpr GLuint kStrokeRectBinding = 0;

class RainProgram {
 public:
  RainProgram();

  // Binds the program, sets its uniforms and the blending of both attachments.
  void use(const ShadingParams& shading, int targetWidth, int targetHeight, int atlasWidth,
           int atlasHeight) const;

 private:
  // uShOrder, uEnvSh, uTransferZonal from a validated SH term.
  void setShUniforms(const ShadingParams& shading) const;

  GlProgram program_;
  GLint targetSize_, hasSh_, shOrder_, envSh_, transferZonal_, hasRadianceMap_, atlasSize_,
      backgroundWeight_;
};

}  // namespace pluvia::gpu
