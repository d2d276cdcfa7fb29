#include "util/median.h"

#include <cmath>

#include <gtest/gtest.h>

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
