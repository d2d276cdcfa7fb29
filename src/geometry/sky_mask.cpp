#include "geometry/sky_mask.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace pluvia {
namespace {

// 255 where the (CV_8U) mask's connected components (4-connected) touch `seeds` (CV_8U).
cv::Mat componentsTouching(const cv::Mat& mask, const cv::Mat& seeds) {
  cv::Mat labels;
  const int count = cv::connectedComponents(mask, labels, 4, CV_32S);
  std::vector<char> keep(count, 0);
  for (int y = 0; y < labels.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    const uchar* s = seeds.ptr<uchar>(y);
    for (int x = 0; x < labels.cols; ++x)
      if (s[x] && l[x] > 0) keep[l[x]] = 1;
  }
  cv::Mat out = cv::Mat::zeros(mask.size(), CV_8U);
  for (int y = 0; y < labels.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    uchar* o = out.ptr<uchar>(y);
    for (int x = 0; x < labels.cols; ++x)
      if (keep[l[x]]) o[x] = 255;
  }
  return out;
}

// Where the candidates are not riddled with specks: small regions left out of them that they
// enclose, holding a pixel too dark for the sky (a window, a stain, a shadowed joint), at more
// than maxSpeckDensity of the pixels around. The sky is clear or smoothly clouded; a wall with
// too few points is speckled even where it is as bright as the sky and meets it at a weak edge.
// A cloud's wisps are left out of the candidates too (textured), but they are as bright as the
// sky: counting them would carve square holes (the window) out of the sky around every cloud.
cv::Mat specklessMask(const cv::Mat& candidate, const cv::Mat& bright,
                      const SkyMaskSettings& settings) {
  const cv::Mat left = candidate == 0;
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(left, labels, stats, centroids, 8, CV_32S);
  std::vector<char> dark(size_t(count), 0);
  for (int y = 0; y < left.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    const uchar* b = bright.ptr<uchar>(y);
    for (int x = 0; x < left.cols; ++x)
      if (!b[x]) dark[size_t(l[x])] = 1;
  }
  std::vector<char> speck(size_t(count), 0);
  for (int l = 1; l < count; ++l) {
    const int x = stats.at<int>(l, cv::CC_STAT_LEFT), y = stats.at<int>(l, cv::CC_STAT_TOP);
    const int area = stats.at<int>(l, cv::CC_STAT_AREA);
    const bool inside = x > 0 && y > 0 && x + stats.at<int>(l, cv::CC_STAT_WIDTH) < left.cols &&
                        y + stats.at<int>(l, cv::CC_STAT_HEIGHT) < left.rows;
    speck[size_t(l)] = inside && area <= settings.maxSpeckAreaPx && dark[size_t(l)];
  }
  cv::Mat specks(left.size(), CV_32F);
  for (int y = 0; y < left.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    float* o = specks.ptr<float>(y);
    for (int x = 0; x < left.cols; ++x) o[x] = speck[size_t(l[x])] ? 1.0f : 0.0f;
  }
  const int window = 2 * settings.speckWindowRadiusPx + 1;
  cv::blur(specks, specks, cv::Size(window, window));
  return specks <= settings.maxSpeckDensity;
}

// The seeds with the regions of `labels` (seed candidates, 0 for none) that lie across a line of
// at most bridgePx from them and meet them in the same colour: a region joins when the mean
// colour of its pixels next to the seeds and that of the seeds' pixels next to it agree within
// bridgeCodes in every channel. Repeated until nothing joins (the sky between two wires joins
// after the sky between the first wire and the top).
cv::Mat bridgedAcrossLines(cv::Mat seeds, const cv::Mat& labels,
                           const std::vector<cv::Mat>& channels, const SkyMaskSettings& settings) {
  const cv::Mat reach = cv::getStructuringElement(
      cv::MORPH_RECT, cv::Size(2 * settings.bridgePx + 1, 2 * settings.bridgePx + 1));
  double maxLabel = 0.0;
  cv::minMaxLoc(labels, nullptr, &maxLabel);
  const size_t count = size_t(maxLabel) + 1, nc = channels.size();
  for (int pass = 0; pass < 16; ++pass) {
    cv::Mat nearSeeds;
    cv::dilate(seeds, nearSeeds, reach);
    // Per region: the mean colour of its pixels near the seeds, and of the seeds' pixels near it
    // (those whose reach holds one of its pixels: a second dilation, of that region's label).
    std::vector<std::vector<double>> regionSum(count, std::vector<double>(nc, 0.0)),
        seedSum(count, std::vector<double>(nc, 0.0));
    std::vector<int> regionCount(count, 0), seedCount(count, 0);
    // Labels as floats (exact up to 2^24): OpenCV dilates no 32-bit integers.
    cv::Mat regionNear = cv::Mat::zeros(labels.size(), CV_32F);
    for (int y = 0; y < labels.rows; ++y)
      for (int x = 0; x < labels.cols; ++x) {
        const int l = labels.at<int>(y, x);
        if (l <= 0 || seeds.at<uchar>(y, x) || !nearSeeds.at<uchar>(y, x)) continue;
        regionNear.at<float>(y, x) = float(l);
        ++regionCount[size_t(l)];
        for (size_t c = 0; c < nc; ++c) regionSum[size_t(l)][c] += channels[c].at<uchar>(y, x);
      }
    cv::Mat seedNear;  // per seed pixel, a region label within reach (the largest: one is enough)
    cv::dilate(regionNear, seedNear, reach);
    for (int y = 0; y < labels.rows; ++y)
      for (int x = 0; x < labels.cols; ++x) {
        const int l = int(seedNear.at<float>(y, x));
        if (l <= 0 || !seeds.at<uchar>(y, x)) continue;
        ++seedCount[size_t(l)];
        for (size_t c = 0; c < nc; ++c) seedSum[size_t(l)][c] += channels[c].at<uchar>(y, x);
      }
    std::vector<char> joins(count, 0);
    bool any = false;
    for (size_t l = 1; l < count; ++l) {
      if (regionCount[l] == 0 || seedCount[l] == 0) continue;
      bool agree = true;
      for (size_t c = 0; c < nc; ++c)
        agree = agree && std::abs(regionSum[l][c] / regionCount[l] -
                                  seedSum[l][c] / seedCount[l]) <= settings.bridgeCodes;
      joins[l] = agree;
      any = any || agree;
    }
    if (!any) break;
    for (int y = 0; y < labels.rows; ++y)
      for (int x = 0; x < labels.cols; ++x)
        if (joins[size_t(std::max(0, labels.at<int>(y, x)))]) seeds.at<uchar>(y, x) = 255;
  }
  return seeds;
}

}  // namespace

std::vector<cv::Mat> colourChannels(const cv::Mat& guide) {
  std::vector<cv::Mat> channels;
  cv::split(guide, channels);
  if (channels.size() == 4) channels.pop_back();
  for (cv::Mat& c : channels) {
    if (c.depth() == CV_8U) continue;
    cv::Mat f;
    c.convertTo(f, CV_32F);
    cv::max(f, 0.0, f);
    cv::pow(f, 1.0 / 2.2, f);
    f.convertTo(c, CV_8U, 255.0);
  }
  return channels;
}

void groundPlane(const Camera& camera, int width, int height, double maxDistanceMeters,
                 cv::Mat& inverseDepth, cv::Mat& sinElevation) {
  inverseDepth = cv::Mat::zeros(height, width, CV_32F);
  sinElevation = cv::Mat::zeros(height, width, CV_32F);
  // Scale from the frame's size to the camera's (the same view at another resolution).
  const double sx = camera.width > 0 ? static_cast<double>(camera.width) / width : 1.0;
  const double sy = camera.height > 0 ? static_cast<double>(camera.height) / height : 1.0;
  const double h = camera.positionMeters.y();
  for (int y = 0; y < height; ++y) {
    float* inv = inverseDepth.ptr<float>(y);
    float* elevation = sinElevation.ptr<float>(y);
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector3d ray =
          camera.worldFromCamera * camera.rayCamera((x + 0.5) * sx, (y + 0.5) * sy);
      const double length = ray.norm();
      elevation[x] = static_cast<float>(ray.y() / length);
      // The ray has camera-space z = -1, so its parameter at the ground is the z-depth.
      if (h > 0 && ray.y() < 0 && h / -ray.y() * length <= maxDistanceMeters)
        inv[x] = static_cast<float>(-ray.y() / h);
    }
  }
}

cv::Mat skyMask(const cv::Mat& guide, const cv::Mat& sampleMask, const cv::Mat& distancePx,
                const cv::Mat& sinElevation, const SkyMaskSettings& settings) {
  const std::vector<cv::Mat> channels = colourChannels(guide);
  const cv::Size size = guide.size();
  const double diagonal = std::hypot(size.width, size.height);
  // Texture: the part of the gradient that does not survive averaging over 9x9 pixels (blur of
  // |g| minus |blur of g|): about zero on a smooth gradient or a soft cloud edge, whose
  // gradients all point the same way, and most of |g| on texture and noise. The largest over
  // the colour channels (a wall and the sky can have the same grey level). The same over 3x3
  // pixels says whether a pixel within the 9x9 window's reach of an edge is textured itself.
  cv::Mat value = channels[0].clone(), edge = cv::Mat::zeros(size, CV_32F), texture = edge.clone(),
          nearTexture = edge.clone();
  const cv::Size window(9, 9), nearWindow(3, 3);
  const auto incoherent = [](const cv::Mat& gx, const cv::Mat& gy, const cv::Mat& magnitude,
                             cv::Size around) {
    cv::Mat meanMagnitude, meanX, meanY, coherent;
    cv::blur(magnitude, meanMagnitude, around);
    cv::blur(gx, meanX, around);
    cv::blur(gy, meanY, around);
    cv::magnitude(meanX, meanY, coherent);
    return cv::Mat(meanMagnitude - coherent);
  };
  for (const cv::Mat& c : channels) {
    cv::max(value, c, value);
    cv::Mat gx, gy, magnitude;
    cv::Sobel(c, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
    cv::Sobel(c, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
    cv::magnitude(gx, gy, magnitude);
    cv::max(edge, magnitude, edge);
    cv::max(texture, incoherent(gx, gy, magnitude, window), texture);
    cv::max(nearTexture, incoherent(gx, gy, magnitude, nearWindow), nearTexture);
  }
  std::vector<uchar> levels(value.begin<uchar>(), value.end<uchar>());
  const size_t p99 = levels.size() * 99 / 100;
  std::nth_element(levels.begin(), levels.begin() + p99, levels.end());
  const double white = std::max<double>(levels[p99], 1.0);
  const cv::Mat brightValue =
      value >= std::max(settings.minBrightness * white, settings.minSkyCode);
  cv::Mat bright = brightValue.clone();
  // Warm colours (red well over blue in display codes: brick, terracotta, skin) are no sky; a
  // sunset's orange sky is taken for the backdrop with them.
  if (channels.size() == 3)
    bright &=
        ~((channels[2] > channels[0] * settings.maxRedOverBlue) & (channels[2] >= channels[1]));
  cv::Mat aboveHorizon(size, CV_8U, cv::Scalar(255));
  if (!sinElevation.empty())
    aboveHorizon = sinElevation > std::sin(settings.minElevationDeg * M_PI / 180.0);
  if (!settings.horizonBoundsSeedsOnly) bright &= aboveHorizon;
  cv::Mat candidate = bright & (texture < settings.maxGradient);
  const cv::Mat speckless = specklessMask(candidate, brightValue, settings);
  candidate &= speckless;
  const double seedDistance = settings.minDistanceFraction * diagonal;
  // Seed regions: touching the top row, and at least as large as a disc of radius seedDistance
  // (smaller ones are gaps between the samples on a wall, not the sky). Edges separate them: a
  // far wall with too few points to show its texture must not join the sky above its top edge.
  const cv::Mat noEdge = edge < 3.0 * settings.maxGradient;
  cv::Mat seedLabels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(
      candidate & noEdge & (distancePx > seedDistance), seedLabels, stats, centroids, 4, CV_32S);
  std::vector<char> keep(count, 0);
  std::vector<char> topAboveHorizon(count, 0);
  for (int x = 0; x < size.width; ++x)
    if (aboveHorizon.at<uchar>(0, x)) topAboveHorizon[seedLabels.at<int>(0, x)] = 1;
  for (int l = 1; l < count; ++l)
    keep[l] = topAboveHorizon[l] &&
              stats.at<int>(l, cv::CC_STAT_AREA) >= M_PI * seedDistance * seedDistance;
  cv::Mat seeds = cv::Mat::zeros(size, CV_8U);
  for (int y = 0; y < size.height; ++y) {
    const int* l = seedLabels.ptr<int>(y);
    uchar* o = seeds.ptr<uchar>(y);
    for (int x = 0; x < size.width; ++x)
      if (keep[l[x]]) o[x] = 255;
  }
  if (cv::countNonZero(seeds) == 0) return seeds;
  seeds = bridgedAcrossLines(seeds, seedLabels, channels, settings);
  // Growing into the margin the seeds leave around the samples, and no farther: through
  // candidates with no edge of their own (a faint roof line stops it), within seedDistance of a
  // seed. Then into the margin the texture test leaves around every edge, its window's
  // half-width (the sky just above a roof or around a cloud fails it): bright, speckless pixels
  // with no edge of their own and untextured over 3x3, joined to the sky through such pixels (a
  // wall's edge or its texture stops it).
  cv::Mat fromSeeds;
  cv::distanceTransform(seeds == 0, fromSeeds, cv::DIST_L2, 3);
  const cv::Mat growable = (distancePx > settings.growMinDistancePx) & noEdge;
  cv::Mat grown = componentsTouching(candidate & growable & (fromSeeds <= seedDistance), seeds);
  cv::Mat nearGrown;
  cv::dilate(grown, nearGrown,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(window.width, window.height)));
  grown = componentsTouching(
      grown | (nearGrown & bright & speckless & growable & (nearTexture < settings.maxGradient)),
      grown);
  // Thin lines across the sky (wires, twigs: the sky on both sides), then holes in the sky
  // holding no sample, not reaching the frame's border: a cloud's edge, a bird.
  cv::morphologyEx(
      grown, grown, cv::MORPH_CLOSE,
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * settings.lineRadiusPx + 1,
                                                            2 * settings.lineRadiusPx + 1)),
      cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
  grown &= sampleMask == 0;
  cv::Mat border = cv::Mat::zeros(size, CV_8U);
  cv::rectangle(border, cv::Rect(0, 0, size.width, size.height), 255, 1);
  const cv::Mat notSky = grown == 0;
  cv::Mat holes = notSky & (componentsTouching(notSky, border | sampleMask) == 0);
  if (!settings.horizonBoundsSeedsOnly) holes &= aboveHorizon;
  return grown | holes;
}

cv::Mat estimateSkyMask(const cv::Mat& guide, const std::optional<Camera>& groundCamera,
                        double groundMaxDistanceMeters, const SkyMaskSettings& settings) {
  const cv::Mat noSamples = cv::Mat::zeros(guide.size(), CV_8U);
  const cv::Mat farFromSamples(guide.size(), CV_32F,
                               cv::Scalar(float(std::hypot(guide.cols, guide.rows))));
  cv::Mat groundInverse, sinElevation;
  if (groundCamera)
    groundPlane(*groundCamera, guide.cols, guide.rows, groundMaxDistanceMeters, groundInverse,
                sinElevation);
  SkyMaskSettings guessed = settings;
  guessed.horizonBoundsSeedsOnly = true;
  return skyMask(guide, noSamples, farFromSamples, sinElevation, guessed);
}

}  // namespace pluvia
