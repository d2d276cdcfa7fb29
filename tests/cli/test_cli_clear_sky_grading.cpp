// Grading never draws the depth guess into the picture: a photo looking up at a building under a
// clear blue sky (cut from the real Venice sunset HDR of ../shared/data, pitched 25 deg up, so the
// guess's level camera puts its horizon across the sky), with birds and two wires painted over
// the sky, rained on with `moderate` at its defaults. Where the depth is a guess, darken, blur and
// fog grade the sky alike on either side of the guess's horizon and of the wires (darken's and
// blur's weights, their AOVs' alpha, the same in every patch of sky), and the graded difference
// (output - plate, rain left out) has no edge the plate does not have. Before the sky finder
// joined the sky across wires and below a guessed horizon, the sky under the first wire took the
// backdrop's weight: the darkening stepped from -18 to -8 codes of blue across the wire.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "envmap/perspective_view.h"
#include "night_plate.h"
#include "optics/environment_file.h"
#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr int kWidth = 480, kHeight = 320;

// The plate, BGR display codes: the view, with dark birds and wires over its sky.
cv::Mat3b clearSkyPlate() {
  const EquirectMap venice =
      optics::loadEnvironment((sharedData() / "hdr/polyhaven_venice_sunset_1k.hdr").string());
  const envmap::RecordedFrame view =
      envmap::recordView(venice, envmap::panPose(130.0, 25.0, 60.0, kWidth), kWidth, kHeight, 0.6);
  cv::Mat3b bgr;
  cv::cvtColor(view.displayRgb8, bgr, cv::COLOR_RGB2BGR);
  const cv::Scalar dark(40, 38, 36);
  for (const cv::Point bird : {cv::Point(70, 40), cv::Point(120, 90), cv::Point(210, 60),
                               cv::Point(160, 150), cv::Point(60, 190), cv::Point(250, 120)}) {
    cv::ellipse(bgr, bird, cv::Size(5, 2), 15.0, 0, 360, dark, cv::FILLED, cv::LINE_AA);
    cv::ellipse(bgr, bird + cv::Point(-4, -2), cv::Size(4, 1), -30.0, 0, 360, dark, cv::FILLED,
                cv::LINE_AA);
  }
  for (int wire = 0; wire < 2; ++wire) {
    std::vector<cv::Point> sag;
    for (int x = 0; x <= kWidth; x += 8)
      sag.emplace_back(x, int(std::lround(60 + 45 * wire + 30e-5 * (x - 200) * (x - 200))));
    cv::polylines(bgr, sag, false, dark, 1, cv::LINE_AA);
  }
  return bgr;
}

// Per pixel, the largest of the three channels' Sobel gradient magnitude (codes a pixel).
cv::Mat1f edgeStrength(const cv::Mat& bgr) {
  cv::Mat3f f;
  bgr.convertTo(f, CV_32F);
  cv::Mat3f gx, gy;
  cv::Sobel(f, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(f, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  cv::Mat1f strength(bgr.size(), 0.0f);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x)
      for (int c = 0; c < 3; ++c)
        strength(y, x) = std::max(strength(y, x), std::hypot(gx(y, x)[c], gy(y, x)[c]));
  return strength;
}

}  // namespace

TEST(CliClearSkyGrading, TheGradedDifferenceHasNoEdgeThePlateLacks) {
  if (!stdfs::exists(sharedData() / "hdr/polyhaven_venice_sunset_1k.hdr"))
    GTEST_SKIP() << "../shared/data is absent";
  const stdfs::path dir = freshTempDir("clear_sky_grading");
  const cv::Mat3b plate = clearSkyPlate();
  ASSERT_TRUE(cv::imwrite((dir / "plate.png").string(), plate));
  const std::vector<std::string> dry{"--set", "rain.enabled=false", "--set",
                                     "splash.enabled=false"};
  std::vector<std::string> args{"render", (dir / "plate.png").string(), "-p", "moderate",
                                "-o",     (dir / "graded.png").string()};
  args.insert(args.end(), dry.begin(), dry.end());
  const auto rendered = runPluvia(args);
  ASSERT_EQ(rendered.exitCode, 0) << rendered.output;
  ASSERT_NE(rendered.output.find("depth: guessed from the plate"), std::string::npos)
      << rendered.output;
  const cv::Mat3b graded = cv::imread((dir / "graded.png").string());
  ASSERT_EQ(graded.size(), plate.size());

  // The weights: every patch of clear sky (above, between and under the wires, and under the
  // guessed horizon, the frame's middle row) as the top's; the building less.
  args[5] = (dir / "graded.exr").string();
  args.insert(args.end(), {"--aov", "darken,blur"});
  ASSERT_EQ(runPluvia(args).exitCode, 0);
  for (const std::string aov : {"darken", "blur"}) {
    const Image grading = readAov(dir / "graded.exr", aov, dir);
    const auto weightAt = [&](int x0, int y0) {
      double sum = 0.0;
      for (int y = y0; y < y0 + 10; ++y)
        for (int x = x0; x < x0 + 10; ++x) sum += grading.pixel(x, y)[3];
      return sum / 100.0;
    };
    const double top = weightAt(20, 5);
    for (const cv::Point sky : {cv::Point(300, 15), cv::Point(15, 80), cv::Point(175, 120),
                                cv::Point(25, 200), cv::Point(145, 205)})
      EXPECT_NEAR(weightAt(sky.x, sky.y), top, 0.01) << aov << " at " << sky;
    EXPECT_LT(weightAt(400, 250), top - 0.2) << aov << " on the building";
  }

  // The difference, offset to mid-grey; its edges, and the plate's grown by 2 px.
  cv::Mat3s difference;
  cv::subtract(graded, plate, difference, cv::noArray(), CV_16S);
  const cv::Mat1f differenceEdges = edgeStrength(difference);
  cv::Mat1b plateEdges = edgeStrength(plate) > 4.0f;
  cv::dilate(plateEdges, plateEdges, cv::Mat(), cv::Point(-1, -1), 2);
  // The grading changes the sky by 10 codes or more (it is not a no-op)...
  const cv::Scalar meanChange = cv::mean(cv::abs(difference)(cv::Rect(0, 0, kWidth, 40)));
  EXPECT_GT(meanChange[0] + meanChange[1] + meanChange[2], 10.0);
  // ... and where its change steps by 1.5 codes a pixel or more, the plate has an edge.
  int unexplained = 0;
  cv::Mat3b marked = graded.clone();
  for (int y = 1; y < kHeight - 1; ++y)
    for (int x = 1; x < kWidth - 1; ++x)
      if (differenceEdges(y, x) >= 1.5f && !plateEdges(y, x)) {
        ++unexplained;
        marked(y, x) = cv::Vec3b(255, 0, 255);
      }
  cv::imwrite((dir / "unexplained.png").string(), marked);
  EXPECT_LT(unexplained, kWidth * kHeight / 1000)
      << unexplained << " pixels where the grading steps without an edge in the plate: "
      << (dir / "unexplained.png").string();
}
