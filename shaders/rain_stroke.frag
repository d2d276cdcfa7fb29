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
flat in vec3 vBead;  // beadCycles, glintMode20, glintMode31

// kOscillationModeRatio, parabolicSine() and localLightBead() of src/rain/streak_types.h: keep
// them in step.
const float kOscillationModeRatio = 1.93649167;
float parabolicSine(float s) {
  float y = 2.0 * (s - floor(s)) - 1.0;
  return -4.0 * y * (1.0 - abs(y));
}
float localLightBead(float cycles, float phase, float mode20, float mode31, float v) {
  float s = phase + cycles * v;
  float x = mode20 * parabolicSine(s) + mode31 * parabolicSine(kOscillationModeRatio * s);
  float r = sqrt(1.0 + x * x) + abs(x);
  return x >= 0.0 ? 1.0 / r : r;
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

  vec3 radiance = vRadiance + localLightBead(vBead.x, vLocal.w, vBead.y, vBead.z, v) * vLocal.rgb;
  oRain = vec4(alpha * radiance, alpha);
}
