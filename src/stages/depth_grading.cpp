#include "stages/depth_grading.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "stages/clip_plate_rain.h"
#include "stages/lamp_keeping.h"
#include "util/parallel.h"

namespace pluvia {

std::vector<float> depthGradingWeights(const Image& image, double distanceMeters) {
  std::vector<float> weight(image.pixelCount(), 1.0f);
  const std::vector<float>* depth = image.findPlane(kDepthPlane);
  if (!depth || distanceMeters <= 0.0) return weight;
  // Depth planes repeat values (a backdrop, the ground along a row): exp() only on a change.
  forEachBlock(weight.size(), size_t(1) << 14, [&](size_t begin, size_t end) {
    float lastDepth = std::numeric_limits<float>::quiet_NaN(), lastWeight = 1.0f;
    for (size_t i = begin; i < end; ++i) {
      const float z = (*depth)[i];
      if (!(z < std::numeric_limits<float>::infinity())) continue;  // sky: the whole path
      if (z != lastDepth) {
        lastDepth = z;
        lastWeight = 1.0f - float(std::exp(-std::max(0.0, double(z)) / distanceMeters));
      }
      weight[i] = lastWeight;
    }
  });
  return weight;
}

GradingAov::GradingAov(const Image& image, std::string name) : name_(std::move(name)) {
  if (image.findPlane(name_ + ".R")) before_ = image.rgba;
}

void GradingAov::finish(Image& image, const std::vector<float>& weight) const {
  if (before_.empty()) return;
  float* planes[3] = {image.plane(name_ + ".R").data(), image.plane(name_ + ".G").data(),
                      image.plane(name_ + ".B").data()};
  std::vector<float>& alpha = image.plane(name_ + ".A");
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    bool changed = false;
    for (int c = 0; c < 3; ++c) {
      planes[c][i] = image.rgba[i * 4 + size_t(c)] - before_[i * 4 + size_t(c)];
      changed = changed || planes[c][i] != 0.0f;
    }
    alpha[i] = weight.empty() ? (changed ? 1.0f : 0.0f) : weight[i];
  }
}

void DepthGradingStage::prepareAhead(ClipContext& clip) {
  if (!overRain_) startPlateRainCheck(clip);
}

void DepthGradingStage::prepare(ClipContext& clip) {
  leftOut_ = leaveOutOnRainedPlate(clip, name_, overRain_);
  if (!leftOut_) findNightPlate(clip);
}

void DepthGradingStage::process(ClipContext& clip, FrameContext& frame) {
  if (leftOut_) return;
  const GradingAov aov(frame.image, name_);
  const KeptLamps lamps(frame.image, frameLampShare(clip, frame));
  const std::vector<float>& weight = weightsOf(frame.image);
  grade_(frame.image, weight);
  lamps.restore(frame.image);
  aov.finish(frame.image, weight);
}

const std::vector<float>& DepthGradingStage::weightsOf(const Image& image) {
  const std::vector<float>* depth = image.findPlane(kDepthPlane);
  // Bit for bit (memcmp): equal bits weigh alike, and the comparison runs at memory speed.
  const bool sameDepth = depth ? weightsDepth_.size() == depth->size() &&
                                     std::memcmp(weightsDepth_.data(), depth->data(),
                                                 depth->size() * sizeof(float)) == 0
                               : weightsDepth_.empty() && weights_.size() == image.pixelCount();
  if (!sameDepth || weights_.size() != image.pixelCount()) {
    weights_ = depthGradingWeights(image, distanceMeters_);
    weightsDepth_ = depth ? *depth : std::vector<float>();
  }
  return weights_;
}

}  // namespace pluvia
