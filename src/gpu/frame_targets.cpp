#include "gpu/frame_targets.h"

#include <algorithm>

#include <fmt/format.h>

#include "gpu/gl_check.h"
#include "gpu/rain_error.h"

namespace pluvia::gpu {

FrameTargets::FrameTargets(int width, int height) : width_(width), height_(height) {
  if (width <= 0 || height <= 0) {
    throwRainError(fmt::format("cannot render rain into {}x{} pixels", width, height));
  }
  GLint maxTextureSize = 0;
  GLint maxViewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTextureSize);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
  if (width > maxTextureSize || height > maxTextureSize || width > maxViewport[0] ||
      height > maxViewport[1]) {
    throwRainError(fmt::format("frame of {}x{} pixels exceeds the GPU's limit of {}x{}", width,
                               height, std::min(maxTextureSize, maxViewport[0]),
                               std::min(maxTextureSize, maxViewport[1])));
  }
  // 32-bit float throughout: the CPU twin and the tests compare against float arithmetic.
  background_ = makeTexture2D(GL_RGBA32F, width, height);
  depth_ = makeTexture2D(GL_R32F, width, height);
  composite_ = makeTexture2D(GL_RGBA32F, width, height);
  rain_ = makeTexture2D(GL_RGBA32F, width, height);
  framebuffer_ = genFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, composite_.id(), 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, rain_.id(), 0);
  const GLenum drawBuffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glDrawBuffers(2, drawBuffers);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throwRainError(fmt::format("RGBA32F framebuffer of {}x{} is incomplete (status 0x{:04x})",
                               width, height, status));
  }
  checkGl(fmt::format("creating {}x{} render targets", width, height));
}

void FrameTargets::begin(const std::vector<float>& backgroundRgba,
                         const std::vector<float>& depthMeters) {
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glBindTexture(GL_TEXTURE_2D, background_.id());
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_FLOAT,
                  backgroundRgba.data());
  glBindTexture(GL_TEXTURE_2D, depth_.id());
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RED, GL_FLOAT, depthMeters.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  // The composite starts as B: a copy on the GPU rather than a second upload.
  glCopyImageSubData(background_.id(), GL_TEXTURE_2D, 0, 0, 0, 0, composite_.id(), GL_TEXTURE_2D, 0,
                     0, 0, 0, width_, height_, 1);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  const GLfloat transparent[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearBufferfv(GL_COLOR, 1, transparent);
  glViewport(0, 0, width_, height_);
  checkGl("uploading the background and depth");
}

void FrameTargets::bindInputs(GLuint backgroundUnit, GLuint depthUnit) const {
  glActiveTexture(GL_TEXTURE0 + backgroundUnit);
  glBindTexture(GL_TEXTURE_2D, background_.id());
  glActiveTexture(GL_TEXTURE0 + depthUnit);
  glBindTexture(GL_TEXTURE_2D, depth_.id());
}

void FrameTargets::readComposite(float* rgba) const {
  readAttachment(GL_COLOR_ATTACHMENT0, rgba);
}

void FrameTargets::readRainLayer(float* rgba) const {
  readAttachment(GL_COLOR_ATTACHMENT1, rgba);
}

void FrameTargets::readAttachment(GLenum attachment, float* rgba) const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_.id());
  glReadBuffer(attachment);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, rgba);
  checkGl("reading back the rain render");
}

}  // namespace pluvia::gpu
