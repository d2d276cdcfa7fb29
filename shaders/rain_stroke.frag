#version 430 core
// Matte, depth test and PRT compositing of one streak fragment (Wang et al., Eq. 2). Coverage
// is decided here from the exact quad at the pixel centre, the same test renderRainCpu()
// makes (src/gpu/rain_cpu.cpp), so the two agree on every pixel not within rounding of an
// edge.
layout(binding = 0) uniform sampler2D uAtlas;        // R32F, GL_LINEAR, CLAMP_TO_EDGE
layout(binding = 1) uniform sampler2D uBackground;   // RGBA32F, texelFetch only
layout(binding = 2) uniform sampler2D uSceneDepth;   // R32F metres, far = 3e38, texelFetch only

uniform vec2 uAtlasSizePx;
uniform float uBackgroundWeight;  // c in C' = C + c * B

flat in vec4 vFrame;
flat in vec4 vStreak;
flat in vec4 vRectPx;
flat in vec3 vRadiance;

// Attachment 0 (starts as the background): blended (SRC_ALPHA, ONE_MINUS_SRC_ALPHA) on RGB,
// (ZERO, ONE) on alpha, so the composite keeps the background's alpha.
layout(location = 0) out vec4 oComposite;
// Attachment 1 (starts transparent black): premultiplied, (ONE, ONE_MINUS_SRC_ALPHA).
layout(location = 1) out vec4 oRain;

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

  ivec2 pixel = ivec2(gl_FragCoord.xy);
  if (vStreak.w > texelFetch(uSceneDepth, pixel, 0).r) discard;

  vec2 atlasPx = vec2(vRectPx.x + u * (vRectPx.z - vRectPx.x),
                      vRectPx.y + v * (vRectPx.w - vRectPx.y));
  float matte = texture(uAtlas, atlasPx / uAtlasSizePx).r;
  float alpha = clamp(matte * vStreak.z, 0.0, 1.0);
  if (alpha <= 0.0) discard;

  vec3 shaded = vRadiance + uBackgroundWeight * texelFetch(uBackground, pixel, 0).rgb;
  oComposite = vec4(shaded, alpha);
  oRain = vec4(alpha * shaded, alpha);
}
