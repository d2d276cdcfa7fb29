#include "derain/clip_derain.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "derain/registration.h"
#include "io/clip_reader.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia::derain {
namespace {

// Windows of `window` frames over `count` frames: 0, window, 2 window, ..., the last one moved
// back so it is full. Each frame is emitted by the first window that holds it.
std::vector<size_t> windowStarts(size_t count, size_t window) {
  std::vector<size_t> starts;
  for (size_t start = 0; start < count; start += window)
    starts.push_back(std::min(start, count - window));
  return starts;
}

}  // namespace

ClipDerainSummary derainClip(const std::string& input, const ClipDerainSettings& settings,
                             const std::function<void(const ClipDerainFrame&)>& emit) {
  const auto started = std::chrono::steady_clock::now();
  if (settings.window < 3)
    throw Error(fmt::format("derain window must be at least 3 frames, got {}", settings.window),
                {"derain", {}, input});
  auto reader = openClip(input);
  std::vector<int64_t> frames;
  for (int64_t f : reader->info().frames)
    if (f >= settings.firstFrame && f <= settings.lastFrame) frames.push_back(f);
  if (frames.size() < 3) {
    throw Error(fmt::format("derain needs at least 3 frames; {} has {} in the range asked for",
                            input, frames.size()),
                {"derain", {}, input});
  }
  const size_t window = std::min(frames.size(), size_t(settings.window));

  ClipDerainSummary summary;
  double residualSquares = 0.0, angleSum = 0.0;
  cv::Vec3d colorSum(0, 0, 0);
  size_t emitted = 0;
  for (size_t start : windowStarts(frames.size(), window)) {
    std::vector<cv::Mat> originals;
    for (size_t i = start; i < start + window; ++i)
      originals.push_back(rgbMat(reader->read(frames[i])));
    const int reference = int(window / 2);
    Registration registration;
    registration.referenceToFrame.assign(window, cv::Matx33d::eye());
    try {
      if (settings.registration) registration = registerFrames(originals, reference);
    } catch (const Error& e) {
      throw Error(fmt::format("{} (frames {}-{} of {})", e.what(), frames[start],
                              frames[start + window - 1], input),
                  {"derain", {}, input});
    }
    if (registration.lockedOff)
      log::info(
          fmt::format("derain: frames {}-{}: camera locked off (phase correlation), not "
                      "resampled",
                      frames[start], frames[start + window - 1]));
    DerainSettings solver = settings.solver;
    if (registration.moving()) solver.registrationErrorPx = kResidualMisregistrationPx;
    const DerainResult result = solveDerain(warpToReference(originals, registration), solver);

    ClipDerainWindow stats;
    stats.firstFrame = frames[start];
    stats.lastFrame = frames[start + window - 1];
    stats.maxShiftPx = registration.moving() ? registration.maxShiftPx : 0.0;
    stats.angleDeg = result.angleDeg;
    stats.iterations = result.iterations;
    stats.residual = result.residual;
    stats.noiseSigma = result.noiseSigma;
    stats.history = result.history;
    summary.windows.push_back(stats);
    log::info(fmt::format(
        "derain: frames {}-{}: {} iterations, angle {:.2f} deg, residual {:.4f}, shift {:.1f} px",
        stats.firstFrame, stats.lastFrame, stats.iterations, stats.angleDeg, stats.residual,
        stats.maxShiftPx));

    for (size_t i = start; i < start + window; ++i) {
      if (i < emitted) continue;
      const int k = int(i - start);
      ClipDerainFrame out;
      out.frame = frames[i];
      out.original = originals[size_t(k)];
      const cv::Mat background = warpToFrame(result.background, registration, k, &out.covered);
      out.clean = out.original.clone();
      background.copyTo(out.clean, out.covered);
      out.matte = warpToFrame(result.alpha[size_t(k)], registration, k);
      out.rainColor = result.rainColor[size_t(k)];
      out.angleDeg = result.angleDeg;
      out.noiseSigma = result.noiseSigma;
      emit(out);
      colorSum += cv::Vec3d(out.rainColor);
      angleSum += result.angleDeg;
      residualSquares += result.residual * result.residual;
      ++emitted;
    }
    summary.iterations = std::max(summary.iterations, result.iterations);
  }
  summary.angleDeg = angleSum / double(emitted);
  summary.rainColor = cv::Vec3f(colorSum / double(emitted));
  summary.residual = std::sqrt(residualSquares / double(emitted));
  summary.seconds = secondsSince(started);
  return summary;
}

}  // namespace pluvia::derain
