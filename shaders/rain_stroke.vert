#version 430 core
// The primitive that holds one streak's quad (from head to tail, widened by widthPx / 2 at both
// ends and widthPx across): a wide line (uLines, vertex 2 * streak + end; the width is draw
// state, chosen by src/gpu/streak_batches.cpp) or two triangles (index 4 * streak + corner, see
// streak_stream.cpp). The fragment shader decides coverage from the exact quad either way. The
// streaks are pulled from a storage buffer, not fed as instances, because llvmpipe's draw
// module runs its whole vertex pipeline once per instance. The per-streak
// colour C (SH term + radiance map term) is computed here, not per fragment: it is constant
// over a streak and this halves the shading cost on software rasterisers. The CPU
// twin of the geometry is src/gpu/streak_quad.h, of the colour src/gpu/streak_radiance.cpp:
// keep them in step.
#include "common_sh.glsl"
#include "common_trig.glsl"

// StreakInstance of rain/streak_types.h, 20 floats.
struct Streak {
  vec4 endsPx;  // headX, headY, tailX, tailY; pixels, y down
  vec4 streak;  // widthPx, alpha, depthMeters, strokeIndex
  vec4 view;    // unit direction camera -> drop, beadCycles
  vec4 local;   // the local lights' radiance RGB, beadPhase
  vec4 glint;   // glintMode20, glintMode31, padding
};
layout(std430, binding = 1) readonly buffer Streaks { Streak streaks[]; };

// Stroke rectangles in atlas pixels: x0, y0, x1, y1.
layout(std430, binding = 0) readonly buffer StrokeRects { vec4 strokeRects[]; };

// The drop's radiance per view direction, equirectangular (image/equirect.h), row 0 at +Y.
layout(binding = 3) uniform sampler2D uRadianceMap;  // RGB32F, texelFetch only

uniform vec2 uTargetSizePx;
uniform bool uLines;  // one line per streak, else two triangles
uniform bool uHasSh;  // the SH term of C: uShOrder, uEnvSh, uTransferZonal
uniform int uShOrder;
uniform vec3 uEnvSh[16];
uniform float uTransferZonal[4];
uniform bool uHasRadianceMap;  // the map term of C

flat out vec4 vFrame;     // head.xy (pixels), axis.xy (unit, head -> tail)
flat out vec4 vStreak;    // widthPx, lengthPx, alpha, depthMeters
flat out vec4 vRectPx;    // the stroke's rectangle in the atlas
flat out vec3 vRadiance;  // C
flat out vec4 vLocal;     // the local lights' radiance RGB (beaded per fragment), beadPhase
flat out vec3 vBead;      // beadCycles, glintMode20, glintMode31

// Same threshold as kDegenerateStreakLengthPx: a shorter streak is a still drop, drawn as a
// square with a vertical axis.
const float kDegenerateLengthPx = 1e-4;
// kCoverageMarginPx of src/gpu/streak_batches.h: the primitive reaches this far past the quad.
const float kCoverageMarginPx = 1.0 / 16.0;
// kViewportGuardBandPx of src/gpu/streak_batches.h: the viewport reaches this far past the
// frame on every side.
const float kViewportGuardBandPx = 64.0;
// GL's diamond-exit rule may pull a line's end in by up to half a pixel.
const float kLineEndSlackPx = 1.0;

// The SH (PRT) term, clamped to >= 0.
vec3 shRadiance(vec3 view) {
  float basis[16];
  shEvaluate(view, basis);
  vec3 radiance = vec3(0.0);
  for (int l = 0; l <= uShOrder; ++l) {
    vec3 band = vec3(0.0);
    for (int m = -l; m <= l; ++m) band += basis[l * l + l + m] * uEnvSh[l * l + l + m];
    radiance += uTransferZonal[l] * band;
  }
  return max(radiance, vec3(0.0));
}

vec3 radianceTexel(int x, int y) {
  return texelFetch(uRadianceMap, ivec2(x, y), 0).rgb;
}

// sampleEquirect() of src/image/equirect.cpp, step for step in float: bilinear between texel
// centres, wrapping around in u and clamped to the first and last rows in v. Done by hand
// with texelFetch because a GL sampler's bilinear weights are fixed point (8 bits on many
// GPUs), far from the CPU twin's float weights; atan2 and acos are common_trig.glsl's.
vec3 sampleRadianceMap(vec3 d) {
  const float kTwoPi = 6.28318530717958648;
  const float kPi = 3.14159265358979324;
  ivec2 size = textureSize(uRadianceMap, 0);
  float u = 0.5 + accurateAtan2(d.x, -d.z) / kTwoPi;
  float v = accurateAcos(clamp(d.y, -1.0, 1.0)) / kPi;
  // Texel coordinates with centres on integers.
  float px = u * float(size.x) - 0.5;
  float py = clamp(v * float(size.y) - 0.5, 0.0, float(size.y - 1));
  float x0f = floor(px);
  float y0f = floor(py);
  float fx = px - x0f;
  float fy = py - y0f;
  // GLSL leaves % of a negative int undefined: wrap in float, exact for these whole numbers.
  int x0 = int(mod(x0f, float(size.x)));
  int x1 = (x0 + 1) % size.x;
  int y0 = int(y0f);
  int y1 = min(y0 + 1, size.y - 1);
  vec3 a = radianceTexel(x0, y0), b = radianceTexel(x1, y0);
  vec3 c = radianceTexel(x0, y1), e = radianceTexel(x1, y1);
  vec3 top = a + fx * (b - a);
  vec3 bottom = c + fx * (e - c);
  return top + fy * (bottom - top);
}

// C: each term only when present, added in the order of streakRadiance() on the CPU.
vec3 streakRadiance(vec3 view) {
  vec3 radiance = vec3(0.0);
  if (uHasSh) radiance = shRadiance(view);
  if (uHasRadianceMap) radiance += sampleRadianceMap(view);
  return radiance;
}

void main() {
  Streak instance = streaks[uLines ? gl_VertexID >> 1 : gl_VertexID >> 2];
  vec4 aEndsPx = instance.endsPx;
  vec4 aStreak = instance.streak;
  float widthPx = aStreak.x;
  // Streaks of zero (or NaN) width or alpha never get here: orderForDrawing() drops them.
  vec2 head = aEndsPx.xy;
  vec2 toTail = aEndsPx.zw - head;
  float lengthPx = sqrt(toTail.x * toTail.x + toTail.y * toTail.y);
  vec2 axis = vec2(0.0, 1.0);
  if (lengthPx > kDegenerateLengthPx) {
    axis = toTail / lengthPx;
  } else {
    lengthPx = 0.0;
  }

  float halfWidth = 0.5 * widthPx;
  vec2 cornerPx;
  if (uLines) {
    // GL widens a line along its minor axis (x or y) and ends it square to that axis: a quad
    // corner sits halfWidth * minor / major further along the line than the quad's end, so
    // the line's ends reach that far past head and tail, plus the slack of the end rule.
    float major = max(abs(axis.x), abs(axis.y));
    float minor = min(abs(axis.x), abs(axis.y));
    float reach = halfWidth * (1.0 + minor / major) + kLineEndSlackPx + kCoverageMarginPx;
    cornerPx = (gl_VertexID & 1) == 0 ? head - axis * reach : head + axis * (lengthPx + reach);
  } else {
    // Corner s (0 left, 1 right seen from head to tail on screen), t (0 head end, 1 tail end).
    int s = gl_VertexID & 1;
    int t = (gl_VertexID >> 1) & 1;
    float grown = halfWidth + kCoverageMarginPx;
    float along = t == 0 ? -grown : lengthPx + grown;
    float across = s == 0 ? -grown : grown;
    cornerPx = vec2(head.x + axis.x * along - axis.y * across,
                    head.y + axis.y * along + axis.x * across);
  }
  // Image rows go to GL rows unflipped (row 0 of the image is GL's y = 0): the framebuffer
  // holds the picture upside down in GL terms and reads back top row first, as Image wants.
  vec2 viewportPx = uTargetSizePx + 2.0 * kViewportGuardBandPx;
  gl_Position = vec4((cornerPx + kViewportGuardBandPx) / viewportPx * 2.0 - 1.0, 0.0, 1.0);

  vFrame = vec4(head, axis);
  vStreak = vec4(widthPx, lengthPx, aStreak.y, aStreak.z);
  vRectPx = strokeRects[int(aStreak.w)];
  vRadiance = streakRadiance(instance.view.xyz);
  vLocal = instance.local;
  vBead = vec3(instance.view.w, instance.glint.xy);
}
