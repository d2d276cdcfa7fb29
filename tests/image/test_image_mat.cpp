// Image <-> cv::Mat: R, G, B keep their order and values; gray goes to all three; alpha is 1.
#include <gtest/gtest.h>

#include "image/image.h"

namespace pluvia {
namespace {

TEST(ImageMat, RgbRoundTripKeepsChannelOrderAndValues) {
  cv::Mat rgb(3, 4, CV_32FC3);
  cv::randu(rgb, -2.0, 5.0);
  const Image image = imageFromMat(rgb);
  EXPECT_EQ(image.pixel(2, 1)[0], rgb.at<cv::Vec3f>(1, 2)[0]);  // R stays first
  EXPECT_EQ(image.pixel(2, 1)[2], rgb.at<cv::Vec3f>(1, 2)[2]);
  EXPECT_EQ(image.pixel(3, 2)[3], 1.0f);
  EXPECT_EQ(cv::norm(rgbMat(image), rgb, cv::NORM_INF), 0.0);
}

TEST(ImageMat, GrayFillsAllThreeChannels) {
  cv::Mat gray(2, 2, CV_32FC1, cv::Scalar(0.25));
  gray.at<float>(1, 0) = 0.75f;
  const Image image = imageFromMat(gray);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(image.pixel(0, 1)[c], 0.75f);
  EXPECT_EQ(image.pixel(1, 1)[1], 0.25f);
}

}  // namespace
}  // namespace pluvia
