#pragma once
// The one median: the middle value of an odd count, the mean of the two middle values of an even
// one, NaN for none. nth_element, so linear time; the values are reordered.
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

template <class T>
T median(std::vector<T> values) {
  return medianInPlace(values.data(), values.size());
}

}  // namespace pluvia
