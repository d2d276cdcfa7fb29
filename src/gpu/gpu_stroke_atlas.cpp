#include "gpu/gpu_stroke_atlas.h"

#include <array>

#include "gpu/gl_check.h"
#include "gpu/rain_inputs.h"

namespace pluvia::gpu {

void GpuStrokeAtlas::upload(const rain::StrokeAtlas& atlas) {
  validateAtlas(atlas);
  if (atlas.width != width_ || atlas.height != height_) {
    texture_ = makeTexture2D(GL_R32F, atlas.width, atlas.height);
    glBindTexture(GL_TEXTURE_2D, texture_.id());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    width_ = atlas.width;
    height_ = atlas.height;
  }
  glBindTexture(GL_TEXTURE_2D, texture_.id());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  // Atlas row 0 (its top) goes to texture row 0, so t = y / height with no flip.
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RED, GL_FLOAT, atlas.alpha.data());
  glBindTexture(GL_TEXTURE_2D, 0);

  if (!rects_.id()) rects_ = genBuffer();
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, rects_.id());
  // An empty buffer cannot be bound to a storage block: keep one zero rectangle then (no
  // streak can use it, validateStreaks sees a count of 0).
  const std::array<float, 4> none{0, 0, 0, 0};
  const bool empty = atlas.rects.empty();
  glBufferData(GL_SHADER_STORAGE_BUFFER,
               static_cast<GLsizeiptr>(sizeof(none) * (empty ? 1 : atlas.rects.size())),
               empty ? none.data() : atlas.rects.data()->data(), GL_STATIC_DRAW);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  strokeCount_ = static_cast<int>(atlas.rects.size());
  checkGl("uploading the stroke atlas");
}

void GpuStrokeAtlas::bind(GLuint textureUnit, GLuint rectBinding) const {
  glActiveTexture(GL_TEXTURE0 + textureUnit);
  glBindTexture(GL_TEXTURE_2D, texture_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, rectBinding, rects_.id());
}

}  // namespace pluvia::gpu
