#include "gpu/gpu_radiance_map.h"

#include "gpu/gl_check.h"

namespace pluvia::gpu {

void GpuRadianceMap::update(const EquirectMap& map) {
  if (map.width == resident_.width && map.height == resident_.height && map.rgb == resident_.rgb) {
    return;
  }
  if (map.width != resident_.width || map.height != resident_.height) {
    texture_ = makeTexture2D(GL_RGB32F, map.width, map.height);
  }
  glBindTexture(GL_TEXTURE_2D, texture_.id());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  // Map row 0 (its top, +Y) goes to texture row 0: texelFetch(y) reads map row y.
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, map.width, map.height, GL_RGB, GL_FLOAT, map.rgb.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  checkGl("uploading the radiance map");
  resident_ = map;
}

void GpuRadianceMap::bind(GLuint textureUnit) const {
  glActiveTexture(GL_TEXTURE0 + textureUnit);
  glBindTexture(GL_TEXTURE_2D, texture_.id());
}

}  // namespace pluvia::gpu
