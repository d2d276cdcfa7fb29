#pragma once
// shaders/rain_stroke.vert + .frag, linked once per variant (with and without a scene depth
// plane), with their uniforms and the blend state.
#include "gpu/gl_objects.h"
#include "rain/streak_types.h"

namespace pluvia::gpu {

// Texture units and the storage bindings the shaders declare (layout(binding = ...)).
inline constexpr GLuint kAtlasUnit = 0;
inline constexpr GLuint kSceneDepthUnit = 2;
inline constexpr GLuint kRadianceMapUnit = 3;
inline constexpr GLuint kStrokeRectBinding = 0;
inline constexpr GLuint kStreakBinding = 1;

class RainProgram {
 public:
  RainProgram();

  // Binds the variant for a frame with or without a scene depth plane, sets its uniforms and
  // the blending of the rain layer.
  void use(const rain::ShadingParams& shading, bool sceneDepth, int targetWidth, int targetHeight,
           int atlasWidth, int atlasHeight) const;
  // Switches the vertex shader of the variant in use between one line and two triangles per
  // streak (see streak_batches.h).
  void setLines(bool lines) const;

 private:
  struct Variant {
    explicit Variant(const char* defines);
    GlProgram program;
    GLint targetSize, lines, hasSh, shOrder, envSh, transferZonal, hasRadianceMap, atlasSize;
  };
  // uShOrder, uEnvSh, uTransferZonal from a validated SH term.
  static void setShUniforms(const Variant& variant, const rain::ShadingParams& shading);

  Variant farScene_;   // no depth plane: no depth fetch
  Variant withDepth_;  // SCENE_DEPTH
  mutable const Variant* inUse_ = nullptr;
};

}  // namespace pluvia::gpu
