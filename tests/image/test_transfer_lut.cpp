// The transfer-curve lookup table (image/transfer_lut.h) against the exact function it samples:
// the built-in config's sRGB and Rec.709 curves both ways through OpenColorIO, and an analytic
// power curve. Tolerance: 1e-6 relative (+1e-9 absolute) everywhere in the table's range, the
// bound transfer_lut.h derives; values outside the range are converted exactly.
#include <gtest/gtest.h>

#include <OpenColorIO/OpenColorIO.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>

#include "image/color.h"
#include "image/transfer_lut.h"

namespace pluvia {
namespace {

namespace OCIO = OCIO_NAMESPACE;

// Values that probe the table: log-uniform over its whole range, every 8- and 16-bit code
// value, node boundaries and their neighbours, and the curves' breakpoints.
std::vector<float> probeValues() {
  std::vector<float> values;
  std::mt19937 random(5);
  std::uniform_real_distribution<float> exponent(-16.0f, 8.0f);
  for (int i = 0; i < 200000; ++i) values.push_back(std::exp2(exponent(random)));
  for (int k = 0; k <= 65535; ++k) values.push_back(k / 65535.0f);
  for (int k = 0; k <= 255; ++k) values.push_back(k / 255.0f);
  for (float edge : {1.0f, 0.5f, 2.0f, 0.04045f, 0.0031308f, 0.018f, 0.081f}) {
    values.push_back(edge);
    values.push_back(std::nextafter(edge, 0.0f));
    values.push_back(std::nextafter(edge, 10.0f));
  }
  return values;
}

// A row image holding `values` in R, a shuffle of them in G and B.
Image rowOf(const std::vector<float>& values) {
  Image image(static_cast<int>(values.size()), 1);
  for (size_t i = 0; i < values.size(); ++i) {
    image.rgba[i * 4 + 0] = values[i];
    image.rgba[i * 4 + 1] = values[(i * 7919) % values.size()];
    image.rgba[i * 4 + 2] = values[(i * 104729) % values.size()];
    image.rgba[i * 4 + 3] = 0.5f;
  }
  return image;
}

// The worst relative error of `lut` against `exact` on `values`.
double worstError(const TransferLut& lut, const TransferLut::ExactRgb& exact,
                  const std::vector<float>& values) {
  Image byTable = rowOf(values);
  Image byExact = byTable;
  lut.apply(byTable.rgba.data(), byTable.pixelCount());
  std::vector<float> rgb(byExact.pixelCount() * 3);
  for (size_t i = 0; i < byExact.pixelCount(); ++i) {
    for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = byExact.rgba[i * 4 + c];
  }
  exact(rgb.data(), byExact.pixelCount());
  double worst = 0.0;
  for (size_t i = 0; i < byTable.pixelCount(); ++i) {
    EXPECT_EQ(byTable.rgba[i * 4 + 3], 0.5f) << "alpha untouched";
    for (int c = 0; c < 3; ++c) {
      const double want = rgb[i * 3 + c], got = byTable.rgba[i * 4 + c];
      worst = std::max(worst, std::abs(got - want) / (std::abs(want) + 1e-3));
      EXPECT_NEAR(got, want, 1e-6 * std::abs(want) + 1e-9) << "value " << byExact.rgba[i * 4 + c];
    }
  }
  return worst;
}

TransferLut::ExactRgb ocioExact(const std::string& from, const std::string& to) {
  const std::string path = testing::TempDir() + "/pluvia_builtin.ocio";
  saveBuiltinConfig(path);
  auto processor = OCIO::Config::CreateFromFile(path.c_str())
                       ->getProcessor(from.c_str(), to.c_str())
                       ->getOptimizedCPUProcessor(OCIO::OPTIMIZATION_LOSSLESS);
  return [processor](float* rgb, size_t count) {
    OCIO::PackedImageDesc packed(rgb, static_cast<long>(count), 1, 3);
    processor->apply(packed);
  };
}

TEST(TransferLut, MatchesOpenColorIoOnTheBuiltInCurves) {
  const std::vector<float> values = probeValues();
  for (auto [from, to] : {std::pair{"sRGB", "linear-rec709"},
                          {"linear-rec709", "sRGB"},
                          {"rec709", "linear-rec709"},
                          {"linear-rec709", "rec709"}}) {
    const TransferLut::ExactRgb exact = ocioExact(from, to);
    const double worst = worstError(TransferLut(exact), exact, values);
    std::cout << from << " -> " << to << ": worst relative error " << worst << "\n";
  }
}

TEST(TransferLut, MatchesAPowerCurveAndPassesOtherValuesToTheExactFunction) {
  size_t exactCalls = 0;
  const TransferLut::ExactRgb cube = [&](float* rgb, size_t count) {
    exactCalls += count;
    for (size_t i = 0; i < count * 3; ++i) rgb[i] = rgb[i] * rgb[i] * rgb[i] + 0.25f;
  };
  const TransferLut lut(cube);
  worstError(lut, cube, probeValues());
  // Outside the table: negative, tiny, huge, NaN, infinite. Each pixel holding one is computed
  // exactly, all of its channels.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Image odd = rowOf({-0.5f, 1e-7f, 300.0f, std::numeric_limits<float>::infinity(), 0.5f});
  odd.rgba[4 * 4 + 1] = 0.5f, odd.rgba[4 * 4 + 2] = 0.5f;  // pixel 4 is all in the table
  odd.rgba[0 * 4 + 1] = nan;
  exactCalls = 0;
  EXPECT_EQ(lut.apply(odd.rgba.data(), odd.pixelCount()), 4u);
  EXPECT_EQ(exactCalls, 4u);
  EXPECT_FLOAT_EQ(odd.rgba[0], -0.5f * 0.25f + 0.25f);
  EXPECT_TRUE(std::isnan(odd.rgba[1]));
  EXPECT_FLOAT_EQ(odd.rgba[4 * 2], 300.0f * 300.0f * 300.0f + 0.25f);
  EXPECT_NEAR(odd.rgba[4 * 4], 0.125f + 0.25f, 1e-7);
  // Zero is exact.
  Image zero = rowOf({0.0f});
  lut.apply(zero.rgba.data(), 1);
  EXPECT_EQ(zero.rgba[0], 0.25f);
}

// Many pixels at once (two at a time with AVX2 where the CPU has it) give the same bits as one
// pixel at a time (the scalar loop), misses and zeros mixed in among the hits.
TEST(TransferLut, ManyPixelsAtOnceGiveTheSameBitsAsOneAtATime) {
  const TransferLut::ExactRgb exact = ocioExact("sRGB", "linear-rec709");
  const TransferLut lut(exact);
  std::vector<float> values = probeValues();
  for (float odd : {-0.25f, 0.0f, 1e-7f, 300.0f, -0.0f}) values.insert(values.begin() + 777, odd);
  Image together = rowOf(values);
  Image oneByOne = together;
  const size_t missesTogether = lut.apply(together.rgba.data(), together.pixelCount());
  size_t missesOneByOne = 0;
  for (size_t i = 0; i < oneByOne.pixelCount(); ++i)
    missesOneByOne += lut.apply(oneByOne.rgba.data() + i * 4, 1);
  EXPECT_EQ(missesTogether, missesOneByOne);
  EXPECT_GT(missesTogether, 0u);
  size_t differing = 0;
  for (size_t i = 0; i < together.rgba.size(); ++i)
    differing +=
        std::bit_cast<uint32_t>(together.rgba[i]) != std::bit_cast<uint32_t>(oneByOne.rgba[i]);
  EXPECT_EQ(differing, 0u);
}

}  // namespace
}  // namespace pluvia
