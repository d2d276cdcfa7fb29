#pragma once
// The radiance map of ShadingParams on the GPU: an RGB32F texture read with texelFetch only,
// because the shader does its own float bilinear lookup (sampleRadianceMap() in
// shaders/rain_stroke.vert). A map changes per clip, not per frame: update() keeps a copy of
// what is resident and uploads only a map that differs from it. Comparing a small map costs
// far less than uploading it, and unlike a pointer or a version number it cannot be fooled by
// a map edited in place.
#include "gpu/gl_objects.h"
#include "image/equirect.h"

namespace pluvia::gpu {

class GpuRadianceMap {
 public:
  // Makes `map` (validated, non-empty) resident unless it already is. The texture is re-made
  // only when the size changes.
  void update(const EquirectMap& map);
  void bind(GLuint textureUnit) const;

 private:
  GlTexture texture_;
  EquirectMap resident_;  // what texture_ holds
};

}  // namespace pluvia::gpu
