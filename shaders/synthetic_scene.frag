#version 430 core
// Shading and exact depth of the synthetic street (src/gpu/synthetic_scene.cpp).
// Output 0: linear RGB (Lambertian, fixed sun) of a procedural texture evaluated from world
// position; output 1: z-depth in metres along the optical axis (+infinity for the sky).
// The texture is value noise over an integer hash of the lattice (no period short of 2^32
// cells) at non-integer lacunarity, so no two places look alike, plus thresholded noise for
// sharp-edged blotches: corners and edges are what feature detectors (SIFT) key on.
in vec3 vWorldMeters;
flat in vec3 vNormal;
flat in float vSurface;

uniform bool uSky;
uniform vec3 uCameraMeters;     // camera centre, world
uniform vec3 uViewAxis;         // unit optical axis (camera -Z) in world space
uniform mat3 uWorldFromCamera;  // for the sky's ray directions
uniform vec3 uFocalCxCy;        // focalPx, cx, cy

layout(location = 0) out vec4 outColor;
layout(location = 1) out float outDepthMeters;

// Keep in step with syntheticSkyRgb() in synthetic_scene.cpp.
const vec3 kSkyHorizon = vec3(0.70, 0.78, 0.88);
const vec3 kSkyZenith = vec3(0.25, 0.42, 0.75);
const vec3 kSunDirection = normalize(vec3(0.45, 0.8, 0.375));  // towards the sun
const float kAmbient = 0.28;
const float kSun = 0.72;

// pcg3d (Jarzynski and Olano 2020): integer arithmetic, so every GPU gives the same bits.
uvec3 pcg3d(uvec3 v) {
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.z;
  v.y += v.z * v.x;
  v.z += v.x * v.y;
  v ^= v >> 16u;
  v.x += v.y * v.z;
  v.y += v.z * v.x;
  v.z += v.x * v.y;
  return v;
}

float lattice(ivec3 cell, uint seed) {
  uvec3 h = pcg3d(uvec3(cell) + uvec3(seed, seed * 7u, seed * 13u));
  return float(h.x >> 8u) * (1.0 / 16777216.0);
}

// Value noise in 0..1 with quintic fade (continuous slope: no grid-line creases).
float valueNoise(vec3 p, uint seed) {
  vec3 cell = floor(p);
  vec3 f = p - cell;
  vec3 u = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
  ivec3 c = ivec3(cell);
  float n000 = lattice(c, seed);
  float n100 = lattice(c + ivec3(1, 0, 0), seed);
  float n010 = lattice(c + ivec3(0, 1, 0), seed);
  float n110 = lattice(c + ivec3(1, 1, 0), seed);
  float n001 = lattice(c + ivec3(0, 0, 1), seed);
  float n101 = lattice(c + ivec3(1, 0, 1), seed);
  float n011 = lattice(c + ivec3(0, 1, 1), seed);
  float n111 = lattice(c + ivec3(1, 1, 1), seed);
  return mix(mix(mix(n000, n100, u.x), mix(n010, n110, u.x), u.y),
             mix(mix(n001, n101, u.x), mix(n011, n111, u.x), u.y), u.z);
}

// Octaves from 0.3 to ~60 cycles per metre. An octave finer than the pixel footprint would
// alias into frame-to-frame flicker, so it fades out as it nears the Nyquist rate.
float fbm(vec3 p, float footprintMeters, uint seed) {
  float sum = 0.0;
  float weightSum = 0.0;
  float frequency = 0.3;
  float amplitude = 1.0;
  for (int octave = 0; octave < 9; ++octave) {
    float visible = 1.0 - smoothstep(0.2, 0.45, frequency * footprintMeters);
    sum += amplitude * visible * (valueNoise(p * frequency, seed + uint(octave)) - 0.5);
    weightSum += amplitude;
    frequency *= 2.13;
    amplitude *= 0.75;
  }
  return clamp(0.5 + sum / weightSum * 2.6, 0.0, 1.0);
}

// Sharp-edged blotches: 1 inside, 0 outside, edges a pixel wide.
float blotches(vec3 p, float frequency, float threshold, float footprintMeters, uint seed) {
  float n =
      valueNoise(p * frequency, seed) * 0.7 + valueNoise(p * frequency * 2.7, seed + 1u) * 0.3;
  float edge = max(footprintMeters * frequency * 0.6, 1e-4);
  return smoothstep(threshold - edge, threshold + edge, n);
}

vec3 skyRgb(float unitUp) {
  return mix(kSkyHorizon, kSkyZenith, sqrt(clamp(unitUp, 0.0, 1.0)));
}

vec3 baseAlbedo(int surface) {
  if (surface == 0) return vec3(0.42, 0.40, 0.38);  // ground: asphalt
  if (surface == 1) return vec3(0.78, 0.56, 0.40);  // left wall: ochre
  if (surface == 2) return vec3(0.60, 0.64, 0.70);  // right wall: grey-blue
  if (surface == 3) return vec3(0.75, 0.45, 0.38);  // back wall: brick
  // Boxes: hues spread round the circle.
  float h = fract(float(surface) * 0.381966);
  return 0.45 + 0.35 * cos(6.2831853 * (h + vec3(0.0, 0.33, 0.67)));
}

void main() {
  if (uSky) {
    vec3 rayCamera = vec3((gl_FragCoord.x - uFocalCxCy.y) / uFocalCxCy.x,
                          -(gl_FragCoord.y - uFocalCxCy.z) / uFocalCxCy.x, -1.0);
    vec3 rayWorld = normalize(uWorldFromCamera * rayCamera);
    outColor = vec4(skyRgb(rayWorld.y), 1.0);
    outDepthMeters = uintBitsToFloat(0x7F800000u);  // +infinity
    return;
  }
  int surface = int(vSurface + 0.5);
  // Metres per pixel on the surface, for the texture's anti-aliasing.
  vec3 dx = dFdx(vWorldMeters);
  vec3 dy = dFdy(vWorldMeters);
  float footprintMeters = max(length(dx), length(dy));
  // Each surface gets its own region of noise space, so parallel faces do not repeat.
  vec3 p = vWorldMeters + vec3(float(surface) * 173.31, float(surface) * 59.17, 0.0);
  uint seed = uint(surface) * 31u + 5u;

  float detail = fbm(p, footprintMeters, seed);
  vec3 albedo = baseAlbedo(surface) * (0.45 + 0.75 * detail);
  // A slow second colour, so large areas differ in hue as well as brightness.
  float tint = valueNoise(p * 0.15, seed + 40u);
  albedo *= mix(vec3(1.08, 0.96, 0.88), vec3(0.88, 0.98, 1.10), tint);
  // Large dark stains and small light flecks, both with sharp edges.
  float stain = blotches(p, 0.6, 0.66, footprintMeters, seed + 50u);
  albedo = mix(albedo, albedo * vec3(0.35, 0.33, 0.30), stain);
  float fleck = blotches(p, 2.5, 0.72, footprintMeters, seed + 60u);
  albedo = mix(albedo, vec3(0.85, 0.83, 0.78), fleck * 0.8);
  // Specks a few centimetres across: fine structure for close-up matching.
  float speck = blotches(p, 9.0, 0.74, footprintMeters, seed + 70u);
  albedo = mix(albedo, albedo * 0.45, speck * 0.8);

  float lambert = max(dot(normalize(vNormal), kSunDirection), 0.0);
  vec3 rgb = clamp(albedo * (kAmbient + kSun * lambert), 0.0, 1.0);
  outColor = vec4(rgb, 1.0);
  // Perspective-correct interpolation makes vWorldMeters exact at the pixel centre, and the
  // z-depth is affine in it: exact to float rounding.
  outDepthMeters = dot(vWorldMeters - uCameraMeters, uViewAxis);
}
