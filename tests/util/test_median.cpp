#include "util/median.h"

#include <cmath>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

namespace pluvia {
namespace {

TEST(Median, OddCountIsTheMiddleValue) {
  EXPECT_EQ(median(std::vector<double>{5.0, 1.0, 4.0, 2.0, 3.0}), 3.0);
  EXPECT_EQ(median(std::vector<float>{7.0f}), 7.0f);
}

TEST(Median, EvenCountIsTheMeanOfTheMiddleTwo) {
  EXPECT_EQ(median(std::vector<double>{4.0, 1.0, 10.0, 2.0}), 3.0);
  float values[] = {8.0f, -2.0f};
  EXPECT_EQ(medianInPlace(values, 2), 3.0f);
}

TEST(Median, NoValuesIsNaN) {
  EXPECT_TRUE(std::isnan(median(std::vector<double>{})));
}

}  // namespace
}  // namespace pluvia

// Every order of five values, with ties (values drawn from a few levels), against medianInPlace.
TEST(Median, MedianOfFiveIsTheMiddleValueInEveryOrder) {
  std::mt19937 random(3);
  std::uniform_int_distribution<int> level(0, 3);
  for (int trial = 0; trial < 2000; ++trial) {
    std::array<float, 5> v;
    for (float& x : v)
      x = trial % 2 ? float(level(random)) : std::uniform_real_distribution<float>(-1, 1)(random);
    std::array<float, 5> sorted = v;
    const float want = pluvia::medianInPlace(sorted.data(), sorted.size());
    std::sort(v.begin(), v.end());
    do {
      EXPECT_EQ(pluvia::median5(v[0], v[1], v[2], v[3], v[4]), want);
    } while (std::next_permutation(v.begin(), v.end()));
  }
}
