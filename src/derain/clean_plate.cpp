// Clean plates of real rain footage: registered temporal medians (clean_plate.h says how).
#include "derain/clean_plate.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "derain/dense_flow.h"
#include "derain/streak_stats.h"
#include "util/error.h"
#include "util/median.h"
#include "util/parallel.h"

namespace pluvia::derain {
namespace {

// Rain-suppressed greys of one frame: float for residuals and the stack, 8-bit for DIS.
struct Grey {
  cv::Mat1f codes;
  cv::Mat1b bytes;
};

// One frame of the stack on frame t's grid.
struct Registered {
  cv::Mat3f colour;
  cv::Mat1f grey;    // rain-suppressed
  cv::Mat1b covers;  // 255 where it may join the median
};

Grey suppressedGrey(const cv::Mat3f& bgr, int diameterPx) {
  const cv::Mat1f luma = lumaOf(bgr, ChannelOrder::bgr);
  const cv::Mat disk = cv::getStructuringElement(cv::MORPH_ELLIPSE, {diameterPx, diameterPx});
  Grey out;
  cv::morphologyEx(luma, out.codes, cv::MORPH_OPEN, disk);
  out.codes.convertTo(out.bytes, CV_8U);
  return out;
}

// The 2r + 1 frames around t as [begin, end), shifted inside the clip at its ends.
std::pair<int, int> windowOf(int t, int frames, int radius) {
  const int size = std::min(frames, 2 * radius + 1);
  const int begin = std::clamp(t - radius, 0, frames - size);
  return {begin, begin + size};
}

// Neighbour s on frame t's grid, by identity or by flow, whichever the residuals favour.
Registered registerNeighbour(const cv::Mat3f& colour, const Grey& neighbour, const Grey& reference,
                             cv::DISOpticalFlow& dis, const CleanPlateSettings& settings,
                             NeighbourRegistration& record) {
  const cv::Mat1b everywhere(reference.codes.size(), uchar(255));
  record.identityResidualCodes =
      trimmedMeanAbsDifference(reference.codes, neighbour.codes, everywhere);
  cv::Mat2f forward;
  dis.calc(reference.bytes, neighbour.bytes, forward);
  const cv::Mat2f points = landingPoints(forward);
  const cv::Mat1b covered = inBounds(points);
  const cv::Mat1f warpedGrey = remapCubic(neighbour.codes, points);
  record.flowResidualCodes = trimmedMeanAbsDifference(reference.codes, warpedGrey, covered);
  const double gain = record.identityResidualCodes - record.flowResidualCodes;
  record.flowUsed = gain > settings.flowGainCodes &&
                    gain > settings.flowGainFraction * record.identityResidualCodes;
  if (!record.flowUsed) return {colour, neighbour.codes, everywhere};

  cv::Mat2f backward;
  dis.calc(neighbour.bytes, reference.bytes, backward);
  // The 1 px alone, without registration.cpp's tenth of the flow's length: with it, this
  // median fell from 34.06 to 33.30 dB on report derain's moving camera (the solve: 32.02 dB
  // with it, 32.09 without).
  const cv::Mat1b consistent =
      forwardBackwardConsistent(forward, backward, points, settings.consistencyPx, 0.0);
  return {remapCubic(colour, points), warpedGrey, covered & consistent};
}

// The stack's median colour everywhere, and its validity (clean_plate.h).
void stackMedian(const std::vector<Registered>& stack, const Grey& reference,
                 const CleanPlateSettings& settings, CleanPlate& out) {
  const cv::Size size = reference.codes.size();
  out.plate.create(size);
  out.valid.create(size);
  const int needed = settings.radiusFrames + 1;
  forEachIndex(size.height, [&](int y) {
    std::vector<float> b(stack.size()), g(stack.size()), r(stack.size()), grey(stack.size());
    for (int x = 0; x < size.width; ++x) {
      int count = 0;
      for (const Registered& frame : stack) {
        if (!frame.covers(y, x)) continue;
        const cv::Vec3f c = frame.colour(y, x);
        b[count] = c[0], g[count] = c[1], r[count] = c[2];
        grey[count] = frame.grey(y, x);
        count += 1;
      }
      // The reference itself always covers, so count >= 1.
      out.plate(y, x) = {medianInPlace(b.data(), size_t(count)),
                         medianInPlace(g.data(), size_t(count)),
                         medianInPlace(r.data(), size_t(count))};
      const float greyMedian = medianInPlace(grey.data(), size_t(count));
      for (int i = 0; i < count; ++i) grey[i] = std::abs(grey[i] - greyMedian);
      const float deviation = medianInPlace(grey.data(), size_t(count));
      const float own = std::abs(reference.codes(y, x) - greyMedian);
      const bool agrees = deviation < settings.agreementCodes && own < settings.agreementCodes;
      out.valid(y, x) = count >= needed && agrees ? 255 : 0;
    }
  });
}

void requireFrames(const std::vector<cv::Mat3f>& frames) {
  if (frames.empty()) throw Error("clean plates: no frames");
  for (const cv::Mat3f& frame : frames) {
    if (frame.empty() || frame.size() != frames.front().size()) {
      throw Error("clean plates: the frames differ in size or one is empty");
    }
  }
}

}  // namespace

std::vector<CleanPlate> cleanPlatesAt(const std::vector<cv::Mat3f>& frames,
                                      const std::vector<int>& at,
                                      const CleanPlateSettings& settings) {
  requireFrames(frames);
  requireDenseFlowSize(frames.front().size(), "the clean plate");
  const int count = int(frames.size());
  for (int t : at)
    if (t < 0 || t >= count)
      throw Error(fmt::format("clean plate: frame {} is outside the {} frames given", t, count));
  // Greys, then every (target, neighbour) registration, then the targets' medians, each step in
  // parallel: a handful of targets alone would leave cores idle (3 targets on 2 cores).
  std::vector<Grey> greys(frames.size());
  forEachIndex(frames.size(), [&](size_t i) {
    greys[i] = suppressedGrey(frames[i], settings.suppressDiameterPx);
  });
  std::vector<CleanPlate> plates(at.size());
  std::vector<std::vector<Registered>> stacks(at.size());
  std::vector<std::pair<size_t, size_t>> pairs;  // (target, place in its stack)
  for (size_t k = 0; k < at.size(); ++k) {
    const int t = at[k];
    const auto [begin, end] = windowOf(t, count, settings.radiusFrames);
    stacks[k].push_back({frames[t], greys[t].codes, cv::Mat1b(frames[t].size(), uchar(255))});
    for (int s = begin; s < end; ++s) {
      if (s == t) continue;
      plates[k].neighbours.emplace_back().frame = s;
      pairs.emplace_back(k, stacks[k].size());
      stacks[k].emplace_back();
    }
  }
  forEachIndex(pairs.size(), [&](size_t i) {
    const auto [k, place] = pairs[i];
    NeighbourRegistration& record = plates[k].neighbours[place - 1];
    const cv::Ptr<cv::DISOpticalFlow> dis = makeDenseFlow();
    stacks[k][place] = registerNeighbour(frames[size_t(record.frame)], greys[size_t(record.frame)],
                                         greys[size_t(at[k])], *dis, settings, record);
  });
  // The invalid areas as wide as what the rain suppression leaves (moving objects, not a broad
  // streak the agreement test refused), grown by the margin.
  const cv::Mat wideOnly = cv::getStructuringElement(
      cv::MORPH_ELLIPSE, cv::Size(settings.suppressDiameterPx, settings.suppressDiameterPx));
  const int side = 2 * std::max(0, settings.distrustMarginPx) + 1;
  const cv::Mat margin = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(side, side));
  for (size_t k = 0; k < at.size(); ++k) {
    stackMedian(stacks[k], greys[size_t(at[k])], settings, plates[k]);
    if (settings.distrustMarginPx <= 0) continue;
    cv::Mat1b wide;
    cv::morphologyEx(plates[k].valid == 0, wide, cv::MORPH_OPEN, wideOnly);
    cv::dilate(wide, wide, margin);
    plates[k].valid.setTo(0, wide);
  }
  return plates;
}

std::vector<CleanPlate> cleanPlates(const std::vector<cv::Mat3f>& frames,
                                    const CleanPlateSettings& settings) {
  std::vector<int> all(frames.size());
  std::iota(all.begin(), all.end(), 0);
  return cleanPlatesAt(frames, all, settings);
}

}  // namespace pluvia::derain
