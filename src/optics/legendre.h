#pragma once
// Legendre polynomials P_0..P_L at x, by the three-term recurrence (stable for |x| <= 1).
#include <vector>

namespace pluvia::optics {

inline void legendrePolynomials(double x, std::vector<double>& p) {
  if (p.empty()) return;
  p[0] = 1.0;
  if (p.size() > 1) p[1] = x;
  for (size_t l = 2; l < p.size(); ++l) {
    p[l] = ((2.0 * l - 1.0) * x * p[l - 1] - (l - 1.0) * p[l - 2]) / double(l);
  }
}

}  // namespace pluvia::optics
