#include "stages/frame_sky.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace pluvia {
namespace {

// Below this phase-correlation peak a neighbour's shift is not trusted. Measured between
// neighbouring frames (at half the sky's size): NTURain's slow pan 0.89-0.94, its vehicle clip
// rb2 0.45-0.61, the Sceaux Castle photo walk 0.33-0.77.
constexpr double kMinShiftResponse = 0.1;
// The frames whose skies are kept for the next frames' votes.
constexpr size_t kKeptFrames = 4;

// `neighbour`'s sky shifted onto `own`'s picture; empty when the shift is not trusted.
cv::Mat placedSky(const SmallSky& own, const SmallSky& neighbour) {
  // At half the sky's size: a shift within 2 px is as good for a vote, at a quarter of the cost.
  cv::Mat ownHalf, neighbourHalf, window;
  cv::pyrDown(own.grey, ownHalf);
  cv::pyrDown(neighbour.grey, neighbourHalf);
  cv::createHanningWindow(window, ownHalf.size(), CV_32F);
  double response = 0.0;
  const cv::Point2d shift = 2.0 * cv::phaseCorrelate(neighbourHalf, ownHalf, window, &response);
  if (!(response >= kMinShiftResponse)) return {};
  const cv::Mat move = (cv::Mat_<double>(2, 3) << 1, 0, shift.x, 0, 1, shift.y);
  cv::Mat placed;
  cv::warpAffine(neighbour.sky, placed, move, neighbour.sky.size(), cv::INTER_NEAREST,
                 cv::BORDER_REPLICATE);
  return placed;
}

}  // namespace

const SmallSky& FrameSky::smallAt(ClipContext& clip, int64_t frame, const Image* image) {
  if (auto found = recent_.find(frame); found != recent_.end()) return found->second;
  if (recent_.size() >= kKeptFrames) recent_.erase(recent_.begin());
  if (image) return recent_[frame] = smallSkyOf(*image, cameraAt_(double(frame)));
  // Not clip.readWorking: the render's reader is decoding the next frames on its own thread.
  if (!neighbours_) neighbours_ = clip.openWorkingReader();
  return recent_[frame] = smallSkyOf(neighbours_(frame), cameraAt_(double(frame)));
}

std::vector<uint8_t> FrameSky::at(ClipContext& clip, int64_t frame, const Image& image) {
  const std::vector<int64_t>& frames = clip.clip->frames;
  const auto here = std::find(frames.begin(), frames.end(), frame);
  const SmallSky own = smallAt(clip, frame, &image);
  if (here == frames.end() || here == frames.begin() || here + 1 == frames.end())
    return fullSizeSky(own.sky, image.width, image.height);
  const cv::Mat before = placedSky(own, smallAt(clip, *(here - 1), nullptr));
  const cv::Mat after = placedSky(own, smallAt(clip, *(here + 1), nullptr));
  if (before.empty() || after.empty()) return fullSizeSky(own.sky, image.width, image.height);
  // Two of three: own and either neighbour, or both neighbours.
  const cv::Mat voted = (own.sky & (before | after)) | (before & after);
  return fullSizeSky(voted, image.width, image.height);
}

}  // namespace pluvia
