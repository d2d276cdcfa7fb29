#include "gpu/rain_program.h"

#include <array>

#include "gpu/gl_check.h"
#include "gpu/shader_program.h"

namespace pluvia::gpu {

RainProgram::RainProgram() : program_(buildProgram("rain_stroke.vert", "rain_stroke.frag")) {
  const GLuint id = program_.id();
  targetSize_ = glGetUniformLocation(id, "uTargetSizePx");
  hasSh_ = glGetUniformLocation(id, "uHasSh");
  shOrder_ = glGetUniformLocation(id, "uShOrder");
  envSh_ = glGetUniformLocation(id, "uEnvSh");
  transferZonal_ = glGetUniformLocation(id, "uTransferZonal");
  hasRadianceMap_ = glGetUniformLocation(id, "uHasRadianceMap");
  atlasSize_ = glGetUniformLocation(id, "uAtlasSizePx");
  backgroundWeight_ = glGetUniformLocation(id, "uBackgroundWeight");
  checkGl("looking up the rain shader's uniforms");
}

void RainProgram::setShUniforms(const ShadingParams& shading) const {
  glUniform1i(shOrder_, shading.shOrder);
  // Always all 16 / 4 entries: the shader reads only up to shOrder, the rest are zeros.
  std::array<float, 16 * 3> envSh{};
  for (size_t i = 0; i < shading.envSh.size(); ++i) {
    for (int c = 0; c < 3; ++c) envSh[i * 3 + c] = shading.envSh[i][c];
  }
  std::array<float, 4> zonal{};
  for (size_t l = 0; l < shading.transferZonal.size(); ++l) zonal[l] = shading.transferZonal[l];
  glUniform3fv(envSh_, 16, envSh.data());
  glUniform1fv(transferZonal_, 4, zonal.data());
}

void RainProgram::use(const ShadingParams& shading, int targetWidth, int targetHeight,
                      int atlasWidth, int atlasHeight) const {
  glUseProgram(program_.id());
  glUniform2f(targetSize_, static_cast<float>(targetWidth), static_cast<float>(targetHeight));
  glUniform2f(atlasSize_, static_cast<float>(atlasWidth), static_cast<float>(atlasHeight));
  glUniform1f(backgroundWeight_, shading.backgroundWeight);
  const bool hasSh = !shading.envSh.empty();
  glUniform1i(hasSh_, hasSh ? 1 : 0);
  // Without the SH term its inputs are unchecked (validateShading) and the shader skips them.
  if (hasSh) setShUniforms(shading);
  glUniform1i(hasRadianceMap_, shading.radianceMap.empty() ? 0 : 1);

  glEnablei(GL_BLEND, 0);
  glBlendEquationSeparatei(0, GL_FUNC_ADD, GL_FUNC_ADD);
  glBlendFuncSeparatei(0, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
  glEnablei(GL_BLEND, 1);
  glBlendEquationSeparatei(1, GL_FUNC_ADD, GL_FUNC_ADD);
  glBlendFuncSeparatei(1, GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  checkGl("setting the rain shader's uniforms");
}

}  // namespace pluvia::gpu
