#pragma once
// The one median (and quantile): the middle value of an odd count, the mean of the two middle
// values of an even one, NaN for none. nth_element, so linear time; the values are reordered.
#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace pluvia {

template <class T>
T medianInPlace(T* values, size_t count) {
  if (count == 0) return std::numeric_limits<T>::quiet_NaN();
  const size_t half = count / 2;
  std::nth_element(values, values + half, values + count);
  const T upper = values[half];
  if (count % 2 == 1) return upper;
  return (upper + *std::max_element(values, values + half)) / T(2);
}

// The median of five values without reordering anything: min and max only, which a loop over
// many samples (a median still of five frames, 8 million samples at 1080p) runs as vector
// instructions. The middle value of the five, as medianInPlace gives it, for values that are not
// NaN: the larger of the two pairs' minima and the smaller of their maxima leave out the least
// and the greatest of a, b, c, d, and e's median with those two is the middle of all five.
template <class T>
T median5(T a, T b, T c, T d, T e) {
  const T low = std::max(std::min(a, b), std::min(c, d));
  const T high = std::min(std::max(a, b), std::max(c, d));
  return std::max(std::min(low, high), std::min(std::max(low, high), e));
}

template <class T>
T median(std::vector<T> values) {
  return medianInPlace(values.data(), values.size());
}

// The q-quantile (0..1) of `values` (reordered), nearest rank q (n - 1) rounded; NaN when empty.
template <class T>
double quantileInPlace(std::vector<T>& values, double q) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * (values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return double(values[k]);
}

}  // namespace pluvia
