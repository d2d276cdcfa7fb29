// pluvia's default drop shading (optics/drop_radiance_map.h): the environment convolved with
// the drop's transfer D(theta), stored as an equirect map. Checked by the white furnace, the
// power kept by area resampling, the Monte-Carlo reference (drop_trace.h) in the built-in
// environment and in real HDR maps, against the paper's SH method, dispersion and stiff optics.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "image/equirect.h"
#include "lab/optics_report.h"
#include "lab/test_environment.h"
#include "optics/drop_radiance_map.h"
#include "optics/drop_shading.h"
#include "optics/drop_trace.h"
#include "optics/drop_transfer.h"
#include "optics/environment_file.h"
#include "test_support.h"

namespace pluvia::optics {
namespace {

using Rgb = std::array<double, 3>;
using Vec = std::array<double, 3>;

constexpr std::array<double, 3> kPlainWater = {kWaterEta, kWaterEta, kWaterEta};

// Mean over R, G, B of |estimate - reference| / reference (the optics report's measure).
double relativeError(const Rgb& estimate, const Rgb& reference) {
  double sum = 0.0;
  for (size_t c = 0; c < 3; ++c) sum += std::abs(estimate[c] - reference[c]) / reference[c];
  return sum / 3.0;
}

// Power of each channel: sum of radiance times texel solid angle.
Rgb power(const EquirectMap& map) {
  Rgb sum = {0.0, 0.0, 0.0};
  for (int y = 0; y < map.height; ++y) {
    const double solidAngle = equirectTexelSolidAngle(map.width, map.height, y);
    for (int x = 0; x < map.width; ++x) {
      for (size_t c = 0; c < 3; ++c) sum[c] += double(map.texel(x, y)[c]) * solidAngle;
    }
  }
  return sum;
}

Rgb lookUp(const EquirectMap& map, const Vec& d) {
  const auto c = sampleEquirect(map, float(d[0]), float(d[1]), float(d[2]));
  return {c[0], c[1], c[2]};
}

struct Errors {
  double defaultMethod = 0.0;
  double paper = 0.0;
};

// Mean relative error over `directions` of the default map and of the paper's method, each
// against the reference traced with `samples` rays.
Errors errorsAgainstReference(const EquirectMap& environment, int directions, int samples) {
  const EquirectMap map =
      buildDropRadianceMap(environment, channelOptics(kPlainWater, kDefaultTerms));
  const PaperShading paper = preparePaperShading(environment, kPlainWater);
  TraceSettings trace;
  trace.samples = samples;
  Errors errors;
  for (const Vec& d : lab::fibonacciDirections(directions)) {
    const Rgb reference = traceDropRadiance(environment, d, kPlainWater, trace);
    errors.defaultMethod += relativeError(lookUp(map, d), reference) / directions;
    errors.paper += relativeError(shadePaper(paper, environment, d), reference) / directions;
  }
  return errors;
}

TEST(DropRadianceMap, WhiteFurnace) {
  // In a uniform environment every view sees radiance * (power of the N terms kept). The
  // kernel is D binned in cos(theta) times exact texel solid angles, so its sum misses the
  // energy only by the binning and sub-sampling of each texel's footprint: 1e-3 relative.
  const EquirectMap uniform = uniformEquirect(256, 128, {1.0f, 2.0f, 3.0f});
  const EquirectMap map = buildDropRadianceMap(uniform, channelOptics(kPlainWater, kDefaultTerms));
  ASSERT_EQ(map.width, RadianceMapSettings{}.outputWidth);
  ASSERT_EQ(map.height, map.width / 2);
  const double energy = transferEnergy(DropOptics{kWaterEta, kDefaultTerms});
  ASSERT_GT(energy, 0.99);
  double worst = 0.0;
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double expected = (c + 1.0) * energy;
        const double e = std::abs(map.texel(x, y)[c] - expected) / expected;
        worst = std::max(worst, e);
        ASSERT_LT(e, 1e-3) << "texel " << x << "," << y << " channel " << c << ": "
                           << map.texel(x, y)[c] << " vs " << expected;
      }
    }
  }
  std::cout << "white furnace: energy " << energy << ", largest relative deviation " << worst
            << "\n";
}

TEST(DropRadianceMap, ResamplingKeepsThePowerOfASun) {
  // One texel 1e6 times brighter than a graded sky, off the equator so that the solid-angle
  // weighting of the rows matters. Sums in double over float texels: 1e-5 relative leaves room
  // for float rounding only; a plain (unweighted) box filter in v is off by percents.
  auto sky = [](int width, int height, int sunX, int sunY) {
    EquirectMap map(width, height);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const float t = float(y) / float(height);
        map.texel(x, y)[0] = 1.0f - 0.5f * t;
        map.texel(x, y)[1] = 0.5f + 0.3f * t + 0.1f * float(x % 7);
        map.texel(x, y)[2] = 0.2f + t * t;
      }
    }
    for (int c = 0; c < 3; ++c) map.texel(sunX, sunY)[c] = 1e6f * float(c + 1);
    return map;
  };
  struct Case {
    int fromWidth, toWidth, sunX, sunY;
  };
  for (const Case& k : {Case{1024, 256, 301, 97}, Case{64, 256, 13, 5}, Case{1024, 256, 700, 3}}) {
    const EquirectMap input = sky(k.fromWidth, k.fromWidth / 2, k.sunX, k.sunY);
    const EquirectMap output = resampleEquirect(input, k.toWidth, k.toWidth / 2);
    ASSERT_EQ(output.width, k.toWidth);
    ASSERT_EQ(output.height, k.toWidth / 2);
    const Rgb before = power(input), after = power(output);
    double worst = 0.0;
    for (size_t c = 0; c < 3; ++c) {
      worst = std::max(worst, std::abs(after[c] - before[c]) / before[c]);
      EXPECT_NEAR(after[c], before[c], 1e-5 * before[c])
          << k.fromWidth << " -> " << k.toWidth << ", channel " << c;
    }
    std::cout << "resample " << k.fromWidth << " -> " << k.toWidth << " (bright texel " << k.sunX
              << "," << k.sunY << "): relative power change " << worst << "\n";
  }
}

TEST(DropRadianceMap, BeatsThePaperAgainstTheReferenceInTheBuiltInEnvironment) {
  // The reference at 65536 rays has ~0.5-1 % noise with the sun in view (drop_trace.h); the
  // default map is expected within 3 % on average, and the paper's 16 SH coefficients, 9 terms
  // and 0.7 B correction at least 5 times worse.
  const Errors errors = errorsAgainstReference(lab::builtinTestEnvironment(), 24, 65536);
  std::cout << "built-in environment, 24 directions: mean relative error default "
            << 100.0 * errors.defaultMethod << " %, paper " << 100.0 * errors.paper << " %\n";
  EXPECT_LT(errors.defaultMethod, 0.03);
  EXPECT_GT(errors.paper, 5.0 * errors.defaultMethod);
}

void checkRealEnvironment(const std::string& relative) {
  const std::filesystem::path data = test::sharedData();
  if (data.empty() || !std::filesystem::exists(data / relative)) {
    GTEST_SKIP() << "no " << relative << " under ../shared/data";
  }
  const EquirectMap environment = loadEnvironment((data / relative).string());
  // Real skies hold small very bright sources (the sun, lamps): 5 % for the default.
  const Errors errors = errorsAgainstReference(environment, 16, 65536);
  std::cout << relative << " (" << environment.width << "x" << environment.height
            << "), 16 directions: mean relative error default " << 100.0 * errors.defaultMethod
            << " %, paper " << 100.0 * errors.paper << " %\n";
  EXPECT_LT(errors.defaultMethod, 0.05);
  EXPECT_GT(errors.paper, errors.defaultMethod);
}

TEST(DropRadianceMap, BeatsThePaperInTheCourtyardHdr) {
  checkRealEnvironment("hdr/blender_world_courtyard.exr");
}

TEST(DropRadianceMap, BeatsThePaperInTheVeniceSunsetHdr) {
  checkRealEnvironment("hdr/polyhaven_venice_sunset_1k.hdr");
}

TEST(DropRadianceMap, DispersionSplitsTheRainbowAndLeavesGreenAlone) {
  // The built-in sun is 30 degrees up at azimuth atan2(x, -z) = 0.6 rad. The primary rainbow
  // lies about 138 degrees from it (D peaks there, theta measured from the view direction):
  // eta 1.331 (R) and 1.338 (B) move that caustic by -0.3 and +0.7 degrees (Descartes), and the
  // sun's image in it is sharp, so the map changes there by far more than float rounding. G
  // keeps eta 1.333 and the same terms, so it must come out the same (1e-6 relative).
  const EquirectMap environment = lab::builtinTestEnvironment();
  const EquirectMap plain =
      buildDropRadianceMap(environment, channelOptics(kPlainWater, kDefaultTerms));
  const EquirectMap dispersed =
      buildDropRadianceMap(environment, channelOptics(kWaterEtaDispersion, kDefaultTerms));
  ASSERT_EQ(plain.width, dispersed.width);
  const double elevation = 30.0 * M_PI / 180.0, azimuth = 0.6;
  const Vec sun = {std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                   -std::cos(elevation) * std::cos(azimuth)};
  double ringRed = 0.0, ringBlue = 0.0, worstGreen = 0.0;
  for (int y = 0; y < plain.height; ++y) {
    for (int x = 0; x < plain.width; ++x) {
      const Vec d = equirectTexelDirection(plain.width, plain.height, x, y);
      const double angle =
          std::acos(std::clamp(d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2], -1.0, 1.0));
      const float* a = plain.texel(x, y);
      const float* b = dispersed.texel(x, y);
      worstGreen = std::max(worstGreen, std::abs(double(b[1]) - a[1]) / a[1]);
      if (std::abs(angle * 180.0 / M_PI - 138.0) < 6.0) {
        ringRed = std::max(ringRed, std::abs(double(b[0]) - a[0]) / a[0]);
        ringBlue = std::max(ringBlue, std::abs(double(b[2]) - a[2]) / a[2]);
      }
    }
  }
  std::cout << "dispersion near the rainbow: largest relative change R " << ringRed << ", B "
            << ringBlue << "; G anywhere " << worstGreen << "\n";
  EXPECT_LT(worstGreen, 1e-6);
  // Measured: 28 % (R) and 40 % (B) at the most affected texel of the ring.
  EXPECT_GT(ringRed, 5e-2);
  EXPECT_GT(ringBlue, 5e-2);
}

TEST(DropRadianceMap, StiffOpticsGiveFiniteNonNegativeMaps) {
  // eta near 1 (a nearly invisible drop: all power straight through), eta 2.5 (strong internal
  // reflection, many caustics), one term and 50 terms.
  const EquirectMap environment = lab::builtinTestEnvironment();
  for (double eta : {1.0001, 2.5}) {
    for (int terms : {1, 50}) {
      const EquirectMap map =
          buildDropRadianceMap(environment, channelOptics({eta, eta, eta}, terms));
      ASSERT_FALSE(map.empty());
      for (size_t i = 0; i < map.rgb.size(); ++i) {
        ASSERT_TRUE(std::isfinite(map.rgb[i]))
            << "eta " << eta << ", N " << terms << ", value " << i;
        ASSERT_GE(map.rgb[i], 0.0f) << "eta " << eta << ", N " << terms << ", value " << i;
      }
    }
  }
}

}  // namespace
}  // namespace pluvia::optics

namespace pluvia::optics {
namespace {

// The map's own formula summed directly, texel by texel, on an environment unlike itself upside
// down (a bright band above the horizon, a ramp in longitude): every texel of both hemispheres
// agrees, so the kernels made for the upper half and used for the mirrored rows of the lower
// half (drop_radiance_map.cpp) are the lower half's own. Tolerance 1e-5 relative (float texels
// of double sums).
TEST(DropRadianceMap, EveryRowMatchesTheDirectSumOfItsDefinition) {
  RadianceMapSettings settings;
  settings.outputWidth = 16;
  settings.inputWidth = 32;
  settings.bins = 256;
  EquirectMap environment(32, 16);
  for (int y = 0; y < environment.height; ++y)
    for (int x = 0; x < environment.width; ++x)
      for (int c = 0; c < 3; ++c)
        environment.texel(x, y)[c] = float(0.2 + 0.05 * x + (y >= 3 && y < 6 ? 4.0 + c : 0.0));
  const std::array<DropOptics, 3> optics = channelOptics(kPlainWater, kDefaultTerms);
  const EquirectMap map = buildDropRadianceMap(environment, optics, settings);
  const TransferTable table = binTransfer(optics[0], settings.bins);

  const int outWidth = settings.outputWidth, outHeight = outWidth / 2;
  const int inWidth = settings.inputWidth, inHeight = inWidth / 2;
  const int ratio = inWidth / outWidth, sub = settings.kernelSubsamples;
  double worst = 0.0;
  for (int row = 0; row < outHeight; ++row) {
    const double thetaOut = M_PI * (row + 0.5) / outHeight;
    for (int i = 0; i < outWidth; ++i) {
      std::array<double, 3> sum = {0.0, 0.0, 0.0};
      for (int inRow = 0; inRow < inHeight; ++inRow) {
        double weight = 0.0;
        std::vector<double> kernel(size_t(inWidth), 0.0);
        for (int a = 0; a < sub; ++a) {
          const double thetaIn = M_PI * (inRow + (a + 0.5) / sub) / inHeight;
          weight += std::sin(thetaIn) * sub;
          for (int s = 0; s < inWidth; ++s)
            for (int b = 0; b < sub; ++b) {
              const double columns = s - 0.5 * ratio + (b + 0.5) / sub;
              const double mu = std::sin(thetaOut) * std::sin(thetaIn) *
                                    std::cos(2.0 * M_PI * columns / inWidth) +
                                std::cos(thetaOut) * std::cos(thetaIn);
              kernel[size_t(s)] += std::sin(thetaIn) * table.at(mu);
            }
        }
        const double scale = equirectTexelSolidAngle(inWidth, inHeight, inRow) / weight;
        for (int s = 0; s < inWidth; ++s) {
          const int q = (ratio * i + s) % inWidth;
          for (int c = 0; c < 3; ++c)
            sum[size_t(c)] += kernel[size_t(s)] * scale * environment.texel(q, inRow)[c];
        }
      }
      for (int c = 0; c < 3; ++c) {
        const double got = map.texel(i, row)[c];
        worst = std::max(worst, std::abs(got - sum[size_t(c)]) / sum[size_t(c)]);
      }
    }
  }
  EXPECT_LT(worst, 1e-5);
}

}  // namespace
}  // namespace pluvia::optics
