#version 430 core
// Matte and depth test of one streak fragment; writes the rain layer of the streaks' own
// radiance, alpha * C, premultiplied. The background never enters here: render() finishes
// Eq. 2 on the read-back layer (see rain_renderer.h), which saves the background upload, its
// per-fragment fetch and a second blended attachment. Coverage is decided here from the exact
// quad at the pixel centre, the same test renderRainCpu() makes (src/gpu/rain_cpu.cpp), so the
// two agree on every pixel not within rounding of an edge.
//
// Compiled twice: with SCENE_DEPTH defined (the frame has a "depth" plane) and without (every
// streak is in front of an infinitely far scene, so the fetch is skipped).
layout(binding = 0) uniform sampler2D uAtlas;  // R32F, GL_LINEAR, CLAMP_TO_EDGE
#ifdef SCENE_DEPTH
layout(binding = 2) uniform sampler2D uSceneDepth;  // R32F metres, far = 3e38, texelFetch only
#endif

uniform vec2 uAtlasSizePx;

flat in vec4 vFrame;
flat in vec4 vStreak;
flat in vec4 vRectPx;
flat in vec3 vRadiance;
flat in vec4 vLocal;
flat in float vBeadCycles;

// kBeadDepth and localLightBead() of src/rain/streak_types.h: keep them in step.
const float kBeadDepth = 0.5;
float localLightBead(float cycles, float phase, float v) {
  float x = phase + cycles * v;
  float f = x - floor(x);
  float g = 4.0 * f * (1.0 - f);
  return 1.0 + kBeadDepth * (2.0 * g - 1.0);
}

// The rain layer (starts transparent black): premultiplied, (ONE, ONE_MINUS_SRC_ALPHA) on all
// four channels.
layout(location = 0) out vec4 oRain;

void main() {
  vec2 head = vFrame.xy;
  vec2 axis = vFrame.zw;
  float widthPx = vStreak.x;
  vec2 rel = gl_FragCoord.xy - head;
  float across = rel.x * -axis.y + rel.y * axis.x;
  float along = rel.x * axis.x + rel.y * axis.y;
  float u = 0.5 + across / widthPx;
  float v = (along + 0.5 * widthPx) / (vStreak.y + widthPx);
  if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0) discard;

#ifdef SCENE_DEPTH
  if (vStreak.w > texelFetch(uSceneDepth, ivec2(gl_FragCoord.xy), 0).r) discard;
#endif

  vec2 atlasPx = vec2(vRectPx.x + u * (vRectPx.z - vRectPx.x),
                      vRectPx.y + v * (vRectPx.w - vRectPx.y));
  float matte = texture(uAtlas, atlasPx / uAtlasSizePx).r;
  float alpha = clamp(matte * vStreak.z, 0.0, 1.0);
  if (alpha <= 0.0) discard;

  vec3 radiance = vRadiance + localLightBead(vBeadCycles, vLocal.w, v) * vLocal.rgb;
  oRain = vec4(alpha * radiance, alpha);
}
