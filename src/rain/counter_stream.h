#pragma once
// A counter-based random stream for splashes: the same key always gives the same numbers, so
// what a frame draws depends on the frame, never on the frames rendered before it.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pluvia::rain {

inline uint64_t mix(uint64_t x) {  // splitmix64's finaliser
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

struct Stream {
  uint64_t state;
  double uniform() { return double(mix(state++) >> 11) * 0x1.0p-53; }
  int poisson(double mean) {
    if (mean > 500.0)  // normal approximation, where Knuth's product would underflow
      return std::max(0, int(std::lround(mean + std::sqrt(mean) * normal())));
    const double limit = std::exp(-mean);
    int k = 0;
    for (double p = uniform(); p > limit; p *= uniform()) ++k;
    return k;
  }
  double normal() {
    const double u1 = std::max(uniform(), 1e-300), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
};

}  // namespace pluvia::rain
