#include "derain/clip_derain.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "derain/camera_speed.h"
#include "derain/registration.h"
#include "image/ops.h"
#include "io/clip_reader.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia::derain {
namespace {

// Windows of `window` frames over `count` frames, each starting `window - overlap` after the
// one before, the last one moved back so it is full.
std::vector<size_t> windowStarts(size_t count, size_t window, size_t overlap) {
  std::vector<size_t> starts;
  for (size_t start = 0;; start += window - overlap) {
    starts.push_back(std::min(start, count - window));
    if (start + window >= count) break;
  }
  return starts;
}

// A frame of the footage with its NaN and infinite values (an EXR's) replaced by 0 and counted
// in a warning, as the render does: the solve's sums and the rain colour would otherwise carry
// them over the whole window.
cv::Mat readFiniteFrame(ClipReader& reader, int64_t frame, const std::string& input) {
  Image image = reader.read(frame);
  if (const size_t bad = ops::replaceNonFinite(image))
    log::warning(
        fmt::format("derain: frame {}: {} NaN/Inf values in {} replaced by 0", frame, bad, input));
  return rgbMat(image);
}

// Frames two windows both solved: the clean plate and the matte cross-faded from the earlier
// window's (weight 1 - t) to the later one's (t), so there is no step between windows.
ClipDerainFrame crossFade(const ClipDerainFrame& earlier, const ClipDerainFrame& later, double t) {
  ClipDerainFrame out = later;
  const cv::Mat both = earlier.covered & later.covered;
  cv::Mat blended;
  cv::addWeighted(earlier.clean, 1.0 - t, later.clean, t, 0.0, blended);
  earlier.clean.copyTo(out.clean, earlier.covered & ~later.covered);
  blended.copyTo(out.clean, both);
  cv::addWeighted(earlier.matte, 1.0 - t, later.matte, t, 0.0, out.matte);
  out.covered = earlier.covered | later.covered;
  out.rainColor = earlier.rainColor * float(1.0 - t) + later.rainColor * float(t);
  // A window that saw the rain's direction outranks one that kept an earlier window's, which
  // outranks one that has only the solver's vertical start.
  auto rank = [](const ClipDerainFrame& f) { return f.angleFound ? 2 : f.angleCarried ? 1 : 0; };
  out.angleFound = earlier.angleFound || later.angleFound;
  out.angleCarried = !out.angleFound && (earlier.angleCarried || later.angleCarried);
  out.angleDeg = rank(earlier) == rank(later)
                     ? (1.0 - t) * earlier.angleDeg + t * later.angleDeg
                     : (rank(later) > rank(earlier) ? later.angleDeg : earlier.angleDeg);
  out.noiseSigma = (1.0 - t) * earlier.noiseSigma + t * later.noiseSigma;
  return out;
}

}  // namespace

std::string describeRainAngle(const ClipDerainSummary& summary) {
  const size_t windows = summary.windows.size();
  if (summary.windowsWithAngle == 0)
    return fmt::format(
        "rain direction not seen (no line in the mattes of any of the {} "
        "windows; taken as vertical)",
        windows);
  return fmt::format(
      "rain angle {:.1f} deg (found in {} of {} windows{})", summary.angleDeg,
      summary.windowsWithAngle, windows,
      summary.windowsWithAngle > 1
          ? fmt::format(", {:.1f} to {:.1f} deg", summary.angleMinDeg, summary.angleMaxDeg)
          : std::string());
}

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
  size_t window = std::min(frames.size(), size_t(settings.window));
  std::vector<cv::Mat> first;  // the first window's frames, when read to measure the camera
  if (settings.registration && window > 3) {
    // A camera that crosses much of the frame within a window leaves its ends too little of the
    // middle frame to register onto: the window is shortened to the camera's speed, measured by
    // registering each frame of the first window onto the one before (the 90th percentile of
    // their shifts; frames far apart may share too few features to measure it directly).
    std::vector<double> shifts;
    for (size_t i = 0; i < window; ++i) {
      first.push_back(readFiniteFrame(*reader, frames[i], input));
      if (i > 0)
        shifts.push_back(
            registerFrames({first[i - 1], first[i]}, 0, /*denseFlow=*/false).maxShiftPx);
    }
    const auto at = shifts.begin() + long(0.9 * double(shifts.size() - 1));
    std::nth_element(shifts.begin(), at, shifts.end());
    const int shortened = windowForCameraSpeed(int(window), *at, first[0].cols);
    if (size_t(shortened) < window) {
      log::info(fmt::format(
          "derain: the camera moves up to {:.0f} px a frame (frames {}-{}, 90th percentile): "
          "windows of {} frames instead of {}, so each end stays within {:g} of the frame's "
          "width of its middle frame",
          *at, frames.front(), frames[window - 1], shortened, window, kMaxSpanOfWidth));
      window = size_t(shortened);
    }
  }
  ClipDerainSummary summary;
  double residualSquares = 0.0, angleSum = 0.0;
  size_t angleFrames = 0;
  std::optional<double> lastFoundAngleDeg = settings.knownAngleDeg;
  cv::Vec3d colorSum(0, 0, 0);
  size_t emitted = 0;
  const auto emitFrame = [&](const ClipDerainFrame& out) {
    emit(out);
    colorSum += cv::Vec3d(out.rainColor);
    if (out.angleFound) angleSum += out.angleDeg, ++angleFrames;
    ++emitted;
  };
  // A quarter of each window is solved again by the next, and cross-faded.
  const size_t overlap = window < frames.size() ? std::max<size_t>(1, window / 4) : 0;
  const std::vector<size_t> starts = windowStarts(frames.size(), window, overlap);
  std::vector<ClipDerainFrame> pending;  // the earlier window's frames the next one also solves
  size_t pendingFirst = 0;               // the index of pending's first frame
  for (size_t w = 0; w < starts.size(); ++w) {
    const size_t start = starts[w];
    const size_t nextStart = w + 1 < starts.size() ? starts[w + 1] : frames.size();
    std::vector<cv::Mat> originals;
    for (size_t i = start; i < start + window; ++i)
      originals.push_back(i < first.size() ? first[i] : readFiniteFrame(*reader, frames[i], input));
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
    for (size_t i = 0; i < registration.placedFrames.size(); ++i)
      log::warning(fmt::format(
          "derain: frame {} has too few features to register onto frame {}; placed with frame "
          "{}'s motion",
          frames[start + size_t(registration.placedFrames[i])], frames[start + size_t(reference)],
          frames[start + size_t(registration.placedWith[i])]));
    if (registration.lockedOff)
      log::info(
          fmt::format("derain: frames {}-{}: camera locked off (phase correlation), not "
                      "resampled",
                      frames[start], frames[start + window - 1]));
    if (registration.motionRejected)
      log::info(fmt::format(
          "derain: frames {}-{}: not registered: the fitted motion (shift {:.1f} px) leaves a "
          "residual of {:.2f} codes against {:.2f} without it (kept only under {:g} of it)",
          frames[start], frames[start + window - 1], registration.maxShiftPx,
          registration.motionResidual, registration.identityResidual, kClearlyLowerResidual));
    else if (registration.moving())
      log::info(fmt::format(
          "derain: frames {}-{}: registered: the fitted motion leaves a residual of {:.2f} codes "
          "against {:.2f} without it{}",
          frames[start], frames[start + window - 1], registration.motionResidual,
          registration.identityResidual,
          registration.denseFrames() == 0
              ? std::string("; no frame left a parallax residual for dense flow")
              : fmt::format("; dense flow on {} of {} frames where the homography left parallax "
                            "(residual {:.2f} codes after it, {:.2f} after the flow)",
                            registration.denseFrames(), window - 1, registration.homographyResidual,
                            registration.flowResidual)));
    DerainSettings solver = settings.solver;
    // A window whose mattes show no direction keeps the last one seen (rain turns slowly, and a
    // window of few frames over a fast pan can hold too little of it); vertical until one is.
    const bool carried = lastFoundAngleDeg.has_value();
    if (carried) solver.initialAngleDeg = *lastFoundAngleDeg;
    if (registration.moving()) solver.registrationErrorPx = kResidualMisregistrationPx;
    const DerainResult result = solveDerain(warpToReference(originals, registration), solver);

    ClipDerainWindow stats;
    stats.firstFrame = frames[start];
    stats.lastFrame = frames[start + window - 1];
    stats.maxShiftPx = registration.moving() ? registration.maxShiftPx : 0.0;
    stats.identityResidual = registration.identityResidual;
    stats.motionResidual = registration.motionResidual;
    stats.registration =
        registration.lockedOff        ? "locked off"
        : registration.motionRejected ? "identity (the motion explained less)"
        : registration.denseFrames() > 0
            ? fmt::format("motion, dense flow on {} frames", registration.denseFrames())
        : registration.moving() ? "motion"
                                : "identity";
    stats.angleDeg = result.angleDeg;
    stats.angleFound = result.angleFound;
    if (result.angleFound) {
      lastFoundAngleDeg = result.angleDeg;
      const bool first = summary.windowsWithAngle++ == 0;
      summary.angleMinDeg =
          first ? result.angleDeg : std::min(summary.angleMinDeg, result.angleDeg);
      summary.angleMaxDeg =
          first ? result.angleDeg : std::max(summary.angleMaxDeg, result.angleDeg);
    }
    stats.iterations = result.iterations;
    stats.residual = result.residual;
    stats.noiseSigma = result.noiseSigma;
    stats.history = result.history;
    summary.windows.push_back(stats);
    log::info(fmt::format(
        "derain: frames {}-{}: {} iterations, {}, residual {:.4f}, shift {:.1f} px",
        stats.firstFrame, stats.lastFrame, stats.iterations,
        stats.angleFound ? fmt::format("angle {:.2f} deg", stats.angleDeg)
        : carried
            ? fmt::format("no rain direction in the mattes (the last one seen, {:.2f} deg, kept)",
                          solver.initialAngleDeg)
            : std::string("no rain direction in the mattes (vertical assumed)"),
        stats.residual, stats.maxShiftPx));

    residualSquares += result.residual * result.residual * double(window);
    std::vector<ClipDerainFrame> next;
    for (size_t i = start; i < start + window; ++i) {
      if (i < emitted) continue;
      const int k = int(i - start);
      ClipDerainFrame out;
      out.frame = frames[i];
      out.original = originals[size_t(k)];
      const cv::Mat background = warpToFrame(result.background, registration, k, &out.covered);
      // What the reference frame did not see (outside it, or disoccluded by parallax) keeps the
      // frame's own value, median-filtered so that its rain goes too: never another frame's.
      cv::medianBlur(out.original, out.clean, 5);
      background.copyTo(out.clean, out.covered);
      out.matte = warpToFrame(result.alpha[size_t(k)], registration, k);
      out.rainColor = result.rainColor[size_t(k)];
      out.angleDeg = result.angleDeg;
      out.angleFound = result.angleFound;
      out.angleCarried = !result.angleFound && carried;
      out.noiseSigma = result.noiseSigma;
      const size_t waiting = i - pendingFirst;  // index among the earlier window's frames
      if (i >= pendingFirst && waiting < pending.size()) {
        const double t = double(waiting + 1) / double(pending.size() + 1);
        out = crossFade(pending[waiting], out, t);
      }
      if (i >= nextStart) {
        next.push_back(std::move(out));
        continue;
      }
      emitFrame(out);
    }
    pending = std::move(next);
    pendingFirst = nextStart;
    summary.iterations = std::max(summary.iterations, result.iterations);
  }
  for (const ClipDerainFrame& out : pending) emitFrame(out);
  summary.angleDeg = angleFrames > 0 ? angleSum / double(angleFrames) : 0.0;
  summary.rainColor = cv::Vec3f(colorSum / double(emitted));
  summary.residual = std::sqrt(residualSquares / double(window * starts.size()));
  summary.seconds = secondsSince(started);
  return summary;
}

}  // namespace pluvia::derain
