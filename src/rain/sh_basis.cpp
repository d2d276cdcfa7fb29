// Real spherical harmonics up to order 3, the CPU twin of shEvaluate() in
// shaders/common_sh.glsl: the two must stay formula for formula identical, because the GPU and
// the CPU renderer are compared pixel by pixel. Constants and signs follow Sloan, "Stupid
// Spherical Harmonics (SH) Tricks" without the Condon-Shortley phase; the order-3 forms use
// x^2 + y^2 + z^2 = 1, so the direction must be a unit vector.
#include "rain/streak_types.h"

namespace pluvia::rain {

std::array<float, 16> shEvaluate(float x, float y, float z) {
  std::array<float, 16> basis;
  // l = 0
  basis[0] = 0.28209479177387814f;
  // l = 1
  basis[1] = 0.4886025119029199f * y;
  basis[2] = 0.4886025119029199f * z;
  basis[3] = 0.4886025119029199f * x;
  // l = 2
  basis[4] = 1.0925484305920792f * x * y;
  basis[5] = 1.0925484305920792f * y * z;
  basis[6] = 0.31539156525252005f * (3.0f * z * z - 1.0f);
  basis[7] = 1.0925484305920792f * x * z;
  basis[8] = 0.5462742152960396f * (x * x - y * y);
  // l = 3
  basis[9] = 0.5900435899266435f * y * (3.0f * x * x - y * y);
  basis[10] = 2.890611442640554f * x * y * z;
  basis[11] = 0.4570457994644658f * y * (5.0f * z * z - 1.0f);
  basis[12] = 0.3731763325901154f * z * (5.0f * z * z - 3.0f);
  basis[13] = 0.4570457994644658f * x * (5.0f * z * z - 1.0f);
  basis[14] = 1.445305721320277f * z * (x * x - y * y);
  basis[15] = 0.5900435899266435f * x * (x * x - 3.0f * y * y);
  return basis;
}

}  // namespace pluvia::rain
