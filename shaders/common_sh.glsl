// Real spherical harmonics up to order 3 (16 functions, index l*l + l + m), the GPU twin of
// shEvaluate() in src/rain/sh_basis.cpp: keep the formulas identical, the CPU renderer is
// compared with this one pixel by pixel. Sloan's constants without the Condon-Shortley phase;
// the order-3 forms assume a unit direction.
void shEvaluate(vec3 d, out float basis[16]) {
  float x = d.x;
  float y = d.y;
  float z = d.z;
  // l = 0
  basis[0] = 0.28209479177387814;
  // l = 1
  basis[1] = 0.4886025119029199 * y;
  basis[2] = 0.4886025119029199 * z;
  basis[3] = 0.4886025119029199 * x;
  // l = 2
  basis[4] = 1.0925484305920792 * x * y;
  basis[5] = 1.0925484305920792 * y * z;
  basis[6] = 0.31539156525252005 * (3.0 * z * z - 1.0);
  basis[7] = 1.0925484305920792 * x * z;
  basis[8] = 0.5462742152960396 * (x * x - y * y);
  // l = 3
  basis[9] = 0.5900435899266435 * y * (3.0 * x * x - y * y);
  basis[10] = 2.890611442640554 * x * y * z;
  basis[11] = 0.4570457994644658 * y * (5.0 * z * z - 1.0);
  basis[12] = 0.3731763325901154 * z * (5.0 * z * z - 3.0);
  basis[13] = 0.4570457994644658 * x * (5.0 * z * z - 1.0);
  basis[14] = 1.445305721320277 * z * (x * x - y * y);
  basis[15] = 0.5900435899266435 * x * (x * x - 3.0 * y * y);
}
