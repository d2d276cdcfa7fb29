// atan2 and acos to about 2 float ulps, for the equirectangular lookup in
// shaders/rain_stroke.vert, whose CPU twin (sampleEquirect() in src/image/equirect.cpp) calls
// the C library. GLSL's built-ins may be much coarser (Mesa's acos errs by ~1.5e-4 rad, which
// moves a lookup in a 128 x 64 map by 3e-3 texel), so they cannot serve. The polynomials and
// range reductions are those of Cephes' atanf.c and asinf.c (S. L. Moshier).

const float kTrigPi = 3.14159265358979324;
const float kTrigHalfPi = 1.57079632679489662;
const float kTrigQuarterPi = 0.785398163397448310;

// atan(x) for |x| <= tan(pi / 8).
float atanKernel(float x) {
  float z = x * x;
  return (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z -
          3.33329491539e-1) * z * x + x;
}

float accurateAtan(float x) {
  float a = abs(x);
  float result;
  if (a > 2.414213562373095) {  // tan(3 pi / 8)
    result = kTrigHalfPi + atanKernel(-1.0 / a);
  } else if (a > 0.4142135623730950) {  // tan(pi / 8)
    result = kTrigQuarterPi + atanKernel((a - 1.0) / (a + 1.0));
  } else {
    result = atanKernel(a);
  }
  return x < 0.0 ? -result : result;
}

// atan2(y, x) with C's treatment of signed zeros: they choose between +pi and -pi behind the
// viewer (u = 1 or u = 0 in the map) and between 0 and pi straight up or down.
float accurateAtan2(float y, float x) {
  float halfTurn = floatBitsToInt(y) < 0 ? -kTrigPi : kTrigPi;
  bool xNegative = floatBitsToInt(x) < 0;  // -0 included
  if (y == 0.0) return xNegative ? halfTurn : 0.0;
  if (x == 0.0) return y < 0.0 ? -kTrigHalfPi : kTrigHalfPi;
  return (xNegative ? halfTurn : 0.0) + accurateAtan(y / x);
}

// asin(x) for |x| <= 0.5.
float asinKernel(float x) {
  float z = x * x;
  return ((((4.2163199048e-2 * z + 2.4181311049e-2) * z + 4.5470025998e-2) * z +
           7.4953002686e-2) * z + 1.6666752422e-1) * z * x + x;
}

// acos(x) for x in [-1, 1]. Near +-1 it goes through sqrt(0.5 (1 -+ x)), exact in float, which
// keeps full precision at the poles where acos is steep.
float accurateAcos(float x) {
  if (x < -0.5) return kTrigPi - 2.0 * asinKernel(sqrt(0.5 * (1.0 + x)));
  if (x > 0.5) return 2.0 * asinKernel(sqrt(0.5 * (1.0 - x)));
  return kTrigHalfPi - asinKernel(x);
}
