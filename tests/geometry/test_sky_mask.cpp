// The sky found in a frame alone (geometry/sky_mask.h): clouds with wisps and a textured wall
// under a blue sky, as on a sunny street plate.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "geometry/sky_mask.h"

namespace pluvia {
namespace {

constexpr int kWidth = 480, kHeight = 320, kSkyRows = 200;

// A blue sky over a wall textured with noise and dark windows; white clouds, one touching the
// top of the frame, each ringed by wisps (scattered bright pixels: textured, as bright as the
// sky). `cloudMask` gets the clouds and their wisps.
cv::Mat sunnyStreet(cv::Mat& cloudMask) {
  cv::Mat img(kHeight, kWidth, CV_8UC3);
  cv::RNG rng(7);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      img.at<cv::Vec3b>(y, x) =
          y < kSkyRows ? cv::Vec3b(uchar(240 - y / 10), 170, 110)
                       : cv::Vec3b::all(uchar(std::clamp(140 + rng.uniform(-60, 60), 0, 255)));
  for (int x = 20; x < kWidth; x += 60)
    cv::rectangle(img, {x, 230, 24, 40}, cv::Scalar::all(40), -1);
  cloudMask = cv::Mat::zeros(img.size(), CV_8U);
  const cv::Point centres[] = {{110, 6}, {300, 110}, {420, 60}};
  const cv::Size axes[] = {{60, 22}, {55, 20}, {35, 14}};
  for (int c = 0; c < 3; ++c) {
    cv::ellipse(img, centres[c], axes[c], 0, 0, 360, cv::Scalar::all(250), -1);
    cv::ellipse(cloudMask, centres[c], axes[c] + cv::Size(3, 3), 0, 0, 360, 255, -1);
    // Wisps: little tufts apart from the cloud, each a 3 x 3 speckle of cloud white and sky.
    for (int i = 0; i < 12; ++i) {
      const double angle = rng.uniform(0.0, 2 * M_PI), reach = rng.uniform(1.4, 2.0);
      const cv::Point p(centres[c].x + int(reach * axes[c].width * std::cos(angle)),
                        centres[c].y + int(reach * axes[c].height * std::sin(angle)));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if ((dx + dy) % 2 == 0 &&
              cv::Rect(0, 0, kWidth, kSkyRows - 8).contains(p + cv::Point(dx, dy)))
            img.at<cv::Vec3b>(p + cv::Point(dx, dy)) = cv::Vec3b(252, 240, 225);
      cv::circle(cloudMask, p, 3, 255, -1);
    }
  }
  return img;
}

double fractionMarked(const cv::Mat& sky, const cv::Mat& where) {
  return double(cv::countNonZero(sky & where)) / std::max(cv::countNonZero(where), 1);
}

TEST(SkyMask, CloudWispsAndATexturedWallLeaveNoHolesInTheBlueSky) {
  cv::Mat clouds;
  const cv::Mat img = sunnyStreet(clouds);
  const cv::Mat sky = estimateSkyMask(img, std::nullopt);
  cv::Mat blueSky = cv::Mat::zeros(img.size(), CV_8U);
  blueSky(cv::Rect(0, 0, kWidth, kSkyRows - 4)).setTo(255);
  blueSky &= clouds == 0;
  // Measured: all of the blue sky and of the rows just above the wall, none of the wall. With a
  // cloud's wisps counted as a wall's specks and the sky grown through the texture test (the
  // rules before): 87 % of the blue sky, cut by squares around the wisps of the cloud at the
  // top, and 65 % of the rows above the wall (the texture test's window reaches over its edge).
  EXPECT_GT(fractionMarked(sky, blueSky), 0.99);
  cv::Mat aboveWall = cv::Mat::zeros(img.size(), CV_8U);
  aboveWall(cv::Rect(0, kSkyRows - 4, kWidth, 2)).setTo(255);
  EXPECT_GT(fractionMarked(sky, aboveWall), 0.95);
  cv::Mat wall = cv::Mat::zeros(img.size(), CV_8U);
  wall(cv::Rect(0, kSkyRows + 2, kWidth, kHeight - kSkyRows - 2)).setTo(255);
  EXPECT_LT(fractionMarked(sky, wall), 0.01);
}

// A bright stucco wall under the sky (textured, no dark specks, a weak edge of 18 grey levels): the
// sky reaches its edge and no farther than the texture test's half-window into it.
TEST(SkyMask, TheSkyStopsAtABrightTexturedWall) {
  cv::Mat img(kHeight, kWidth, CV_8UC3);
  cv::RNG rng(3);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      img.at<cv::Vec3b>(y, x) =
          y < kSkyRows ? cv::Vec3b::all(240) : cv::Vec3b::all(uchar(222 + rng.uniform(-16, 17)));
  const cv::Mat sky = estimateSkyMask(img, std::nullopt);
  cv::Mat lowSky = cv::Mat::zeros(img.size(), CV_8U), wall = lowSky.clone();
  lowSky(cv::Rect(0, kSkyRows - 20, kWidth, 18)).setTo(255);
  wall(cv::Rect(0, kSkyRows + 6, kWidth, kHeight - kSkyRows - 6)).setTo(255);
  // Measured: all of the sky's last rows and none of the wall from 6 rows under its edge.
  // Growing through bright pixels with no edge as far as the seeds reach (17 px here), textured
  // or not, took 11 % of that wall: its rows down to about 18 px under the edge.
  EXPECT_GT(fractionMarked(sky, lowSky), 0.99);
  EXPECT_LT(fractionMarked(sky, wall), 0.01);
}

// A smooth, bright brick wall reaching the top of the frame beside the sky: warm, so no sky.
TEST(SkyMask, ABrickWallIsNoSky) {
  cv::Mat img(kHeight, kWidth, CV_8UC3, cv::Scalar(60, 60, 60));
  img(cv::Rect(0, 0, kWidth / 2, kSkyRows)).setTo(cv::Scalar(240, 232, 225));  // BGR
  img(cv::Rect(kWidth / 2, 0, kWidth / 2, kSkyRows)).setTo(cv::Scalar(150, 175, 235));
  const cv::Mat sky = estimateSkyMask(img, std::nullopt);
  cv::Mat left = cv::Mat::zeros(img.size(), CV_8U), right = left.clone();
  left(cv::Rect(0, 0, kWidth / 2 - 6, kSkyRows - 6)).setTo(255);
  right(cv::Rect(kWidth / 2 + 6, 0, kWidth / 2 - 6, kSkyRows - 6)).setTo(255);
  // Measured: all of the sky, none of the brick (red 1.57 times blue); without the warm rule,
  // all of the brick too.
  EXPECT_GT(fractionMarked(sky, left), 0.99);
  EXPECT_LT(fractionMarked(sky, right), 0.01);
}

// A camera looking down at a wet road: a smooth grey, lighter toward the far (top) edge, with
// faint ripples. Relative to the frame's own brightest pixels its top passes for sky; the sky
// lights the scene, so it sits higher in the range than any part of a road exposed for.
TEST(SkyMask, ADimRoadFillingTheFrameIsNoSky) {
  cv::Mat road(kHeight, kWidth, CV_8UC3);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      road.at<cv::Vec3b>(y, x) =
          cv::Vec3b::all(uchar(120 - 60 * y / kHeight + 2 * std::sin(x * 0.3 + y * 0.2)));
  cv::Mat top = cv::Mat::zeros(road.size(), CV_8U);
  top(cv::Rect(0, 0, kWidth, kHeight / 3)).setTo(255);
  // Measured: none of it. The same frame twice as bright (a grey sky at codes 180-240 above a
  // lighter ground), and the road itself with no absolute floor: its top third is sky.
  EXPECT_EQ(cv::countNonZero(estimateSkyMask(road, std::nullopt)), 0);
  SkyMaskSettings relativeOnly;
  relativeOnly.minSkyCode = 0.0;
  EXPECT_GT(fractionMarked(estimateSkyMask(road, std::nullopt, 100.0, relativeOnly), top), 0.9);
  EXPECT_GT(fractionMarked(estimateSkyMask(road * 2.0, std::nullopt), top), 0.9);
}

}  // namespace
}  // namespace pluvia
