#include "gpu/rain_program.h"

#include <array>

#include "gpu/gl_check.h"
#include "gpu/shader_program.h"

namespace pluvia::gpu {

RainProgram::Variant::Variant(const char* defines)
    : program(buildProgram("rain_stroke.vert", "rain_stroke.frag", defines)) {
  const GLuint id = program.id();
  targetSize = glGetUniformLocation(id, "uTargetSizePx");
  lines = glGetUniformLocation(id, "uLines");
  hasSh = glGetUniformLocation(id, "uHasSh");
  shOrder = glGetUniformLocation(id, "uShOrder");
  envSh = glGetUniformLocation(id, "uEnvSh");
  transferZonal = glGetUniformLocation(id, "uTransferZonal");
  hasRadianceMap = glGetUniformLocation(id, "uHasRadianceMap");
  atlasSize = glGetUniformLocation(id, "uAtlasSizePx");
  checkGl("looking up the rain shader's uniforms");
}

RainProgram::RainProgram() : farScene_(""), withDepth_("#define SCENE_DEPTH\n") {}

void RainProgram::setShUniforms(const Variant& variant, const rain::ShadingParams& shading) {
  glUniform1i(variant.shOrder, shading.shOrder);
  // Always all 16 / 4 entries: the shader reads only up to shOrder, the rest are zeros.
  std::array<float, 16 * 3> envSh{};
  for (size_t i = 0; i < shading.envSh.size(); ++i) {
    for (int c = 0; c < 3; ++c) envSh[i * 3 + c] = shading.envSh[i][c];
  }
  std::array<float, 4> zonal{};
  for (size_t l = 0; l < shading.transferZonal.size(); ++l) zonal[l] = shading.transferZonal[l];
  glUniform3fv(variant.envSh, 16, envSh.data());
  glUniform1fv(variant.transferZonal, 4, zonal.data());
}

void RainProgram::use(const rain::ShadingParams& shading, bool sceneDepth, int targetWidth,
                      int targetHeight, int atlasWidth, int atlasHeight) const {
  const Variant& variant = sceneDepth ? withDepth_ : farScene_;
  inUse_ = &variant;
  glUseProgram(variant.program.id());
  glUniform2f(variant.targetSize, static_cast<float>(targetWidth),
              static_cast<float>(targetHeight));
  glUniform2f(variant.atlasSize, static_cast<float>(atlasWidth), static_cast<float>(atlasHeight));
  const bool hasSh = !shading.envSh.empty();
  glUniform1i(variant.hasSh, hasSh ? 1 : 0);
  // Without the SH term its inputs are unchecked (validateShading) and the shader skips them.
  if (hasSh) setShUniforms(variant, shading);
  glUniform1i(variant.hasRadianceMap, shading.radianceMap.empty() ? 0 : 1);

  // The premultiplied rain layer: out = src + (1 - src.a) * dst on all four channels.
  glEnablei(GL_BLEND, 0);
  glBlendEquationSeparatei(0, GL_FUNC_ADD, GL_FUNC_ADD);
  glBlendFuncSeparatei(0, GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  checkGl("setting the rain shader's uniforms");
}

void RainProgram::setLines(bool lines) const {
  glUniform1i(inUse_->lines, lines ? 1 : 0);
}

}  // namespace pluvia::gpu
