#include "gpu/frame_targets.h"

#include <algorithm>

#include <fmt/format.h>

#include "gpu/gl_check.h"
#include "gpu/rain_error.h"
#include "gpu/streak_batches.h"

namespace pluvia::gpu {

FrameTargets::FrameTargets(int width, int height) : width_(width), height_(height) {
  if (width <= 0 || height <= 0) {
    throwRainError(fmt::format("cannot render rain into {}x{} pixels", width, height));
  }
  GLint maxTextureSize = 0;
  GLint maxViewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTextureSize);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
  const int guard = 2 * kViewportGuardBandPx;
  if (width > maxTextureSize || height > maxTextureSize || width + guard > maxViewport[0] ||
      height + guard > maxViewport[1]) {
    throwRainError(fmt::format("frame of {}x{} pixels exceeds the GPU's limit of {}x{}", width,
                               height, std::min(maxTextureSize, maxViewport[0]),
                               std::min(maxTextureSize, maxViewport[1])));
  }
  // 32-bit float throughout: the CPU twin and the tests compare against float arithmetic.
  depth_ = makeTexture2D(GL_R32F, width, height);
  rain_ = makeTexture2D(GL_RGBA32F, width, height);
  framebuffer_ = genFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, rain_.id(), 0);
  const GLenum drawBuffers[] = {GL_COLOR_ATTACHMENT0};
  glDrawBuffers(1, drawBuffers);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throwRainError(fmt::format("RGBA32F framebuffer of {}x{} is incomplete (status 0x{:04x})",
                               width, height, status));
  }
  checkGl(fmt::format("creating {}x{} render targets", width, height));
}

void FrameTargets::begin(const std::vector<float>* depthMeters) {
  if (depthMeters) {
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glBindTexture(GL_TEXTURE_2D, depth_.id());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RED, GL_FLOAT, depthMeters->data());
    glBindTexture(GL_TEXTURE_2D, 0);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  const GLfloat transparent[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearBufferfv(GL_COLOR, 0, transparent);
  glViewport(-kViewportGuardBandPx, -kViewportGuardBandPx, width_ + 2 * kViewportGuardBandPx,
             height_ + 2 * kViewportGuardBandPx);
  checkGl("uploading the scene depth");
}

void FrameTargets::bindSceneDepth(GLuint depthUnit) const {
  glActiveTexture(GL_TEXTURE0 + depthUnit);
  glBindTexture(GL_TEXTURE_2D, depth_.id());
}

void FrameTargets::readRainLayer(float* rgba) const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_.id());
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, rgba);
  checkGl("reading back the rain render");
}

}  // namespace pluvia::gpu
