#include "lab/rain_match.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>
#include <Eigen/Dense>

#include "lab/real_rain_clip.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia::lab {
namespace {

// How each ratio of the typical factor (derain::ratiosToReal's, by name) answers the rate, the
// exposure and the farthest drops drawn (d log ratio / d log setting). The exposure's column was
// measured on NTURain's plates with `gentle` (1/1000, 1/500 and 1/250 s): the length grows as
// exposure^0.4, the brightness (dI and peak) falls as exposure^-0.39 (a drop's light spread along
// a longer streak) and the count as exposure^-0.2 (longer streaks are fainter, fewer pass the
// threshold); the coverage is the count times the length. The rate moves the count and the
// coverage and not the brightness (on NTURain 4 to 8 mm/h moved dI p90 by 3 %). The far column was
// measured there with `moderate` at 1/1000 s, rain.far_m from 4 to 2 m: the count fell as
// far^1.14 and the coverage as far^0.89, the brightness rose as far^-0.12 (the faint far streaks
// gone); from 8 to 4 m the count fell only as far^0.39: the response steepens as the rain thins
// to the near drops, so a step moves far_m by at most kMaxFarStepFactor. The opacity is left where
// the base preset has it (1, the physical streak): on the example street (2.3 to 3.2 at 1/255 s)
// it moved the count as opacity^1.9, as a rate would, and the brightness as opacity^0.03, so a
// search moving it traded it against the rate (12 mm/h matched as 0.8 mm/h at opacity 5).
struct RatioResponse {
  const char* ratio;  // derain::ratiosToReal's name
  double rate, exposure, far;
};
constexpr RatioResponse kRatioResponses[] = {
    {"coverage", 1.0, 0.2, 0.89},     {"deltaP90", 0.0, -0.39, -0.12},
    {"deltaP99", 0.0, -0.39, -0.06},  {"streaksPerMpx", 1.0, -0.2, 1.14},
    {"lengthP50Px", 0.0, 0.4, -0.04}, {"widthP50Px", 0.0, 0.0, -0.05},
    {"peakP90", 0.0, -0.39, -0.12}};

// The ratios the search fits: derain::ratiosToReal's but the elongation by light, which `report
// realism` judges and the search does not fit. It grows as exposure^0.5 (NTURain with `hard`:
// 4.18 at 1/867 s, 7.80 at 1/250 s) and hardly answers the depth (4.22 to 4.14 for far_m 1 to
// 4 m); fitted with that response, the search on pluvia's own rain of known rate (the CliMatch
// test) stopped at far_m 1.83 m against the true 2.48 (a valley between the rate and the depth
// that the fixed responses do not cross) and on NTURain it moved nothing (249 mm/h at 1/1129 s,
// the streaks still half as elongated as real): no rate, shutter and depth give real rain's
// shape and its light together, so fitting the shape only trades the light away.
std::vector<std::pair<std::string, double>> fittedRatios(const derain::StreakStats& rendered,
                                                         const derain::StreakStats& reference) {
  std::vector<std::pair<std::string, double>> ratios = derain::ratiosToReal(rendered, reference);
  std::erase_if(ratios, [](const auto& r) { return r.first == "elongationByLight"; });
  return ratios;
}

// The response's row for `ratio`; every ratio the typical factor averages has one.
Eigen::RowVector3d responseOf(const std::string& ratio) {
  for (const RatioResponse& r : kRatioResponses)
    if (ratio == r.ratio) return {r.rate, r.exposure, r.far};
  throw Error(fmt::format("match: no response for the ratio {}", ratio));
}

// The step is the one the response says lowers the typical factor most: the mean |log ratio|
// after it, searched on a grid of log steps this fine within the largest step. The mean of
// absolute values has flat valleys (between matching the count and matching the coverage, say),
// so a small cost on the step's size picks the shortest move along them.
constexpr double kStepGridLog = 0.01;
constexpr double kStepSizeCost = 0.01;
// Streak angle per m/s of wind across the view before two steps give the secant: a 4.5 m/s fall.
constexpr double kDegreesPerWindStart = -180.0 / M_PI / 4.5;
// No step moves the rate or the exposure by more than this factor, nor rain.far_m by more than
// kMaxFarStepFactor: with the whole factor a step from 8 m went to the 1 m floor on NTURain.
constexpr double kMaxStepFactor = 3.0;
constexpr double kMaxFarStepFactor = 2.0;

// The match weighs the angle beside the typical factor (which leaves it out): a step's score is
// typical * exp(|angle error| / kAngleScaleDeg).
constexpr double kAngleScaleDeg = 10.0;

double score(const RainMatchStep& step, const derain::StreakStats& target, bool angleMatched) {
  if (!angleMatched) return step.typical;
  const double angleError = std::abs(step.stats.angleDeg - target.angleDeg);
  return step.typical * (std::isfinite(angleError) ? std::exp(angleError / kAngleScaleDeg) : 1.0);
}

// `from`'s look with the rate, the exposure and the farthest drops moved by `share` of the step
// that the response predicts lowers the typical factor most, and the wind by the angle's own
// secant.
RainLook moved(const RainMatchStep& from, const derain::StreakStats& target, double share,
               double degreesPerWind, double minFarMeters) {
  RainLook look = from.look;
  const int count = int(from.ratios.size());
  Eigen::VectorXd logRatios(count);
  Eigen::MatrixX3d response(count, 3);
  for (int i = 0; i < count; ++i) {
    logRatios[i] = std::log(from.ratios[size_t(i)].second);
    response.row(i) = responseOf(from.ratios[size_t(i)].first);
  }
  if (count > 0 && logRatios.allFinite()) {
    const int reach = int(std::lround(std::log(kMaxStepFactor) / kStepGridLog));
    const int farReach = int(std::lround(std::log(kMaxFarStepFactor) / kStepGridLog));
    Eigen::Vector3d step(0.0, 0.0, 0.0);
    double bestCost = INFINITY;
    for (int a = -reach; a <= reach; ++a)
      for (int e = -reach; e <= reach; ++e)
        for (int f = -farReach; f <= farReach; ++f) {
          const Eigen::Vector3d candidate(a * kStepGridLog, e * kStepGridLog, f * kStepGridLog);
          const double cost = (logRatios + response * candidate).cwiseAbs().mean() +
                              kStepSizeCost * candidate.squaredNorm();
          if (cost < bestCost) bestCost = cost, step = candidate;
        }
    step *= share;
    look.rateMmPerHour = std::clamp(look.rateMmPerHour * std::exp(step[0]), 0.1, 300.0);
    look.exposureSeconds = std::clamp(look.exposureSeconds * std::exp(step[1]), 1e-4, 0.5);
    look.farMeters = std::clamp(look.farMeters * std::exp(step[2]), minFarMeters, 100.0);
  }
  const double angleError = target.angleDeg - from.stats.angleDeg;
  if (!look.baseWind && std::isfinite(angleError))
    look.windRightMetersPerSecond =
        std::clamp(look.windRightMetersPerSecond + angleError / degreesPerWind, -15.0, 15.0);
  return look;
}

// The angle's response to the wind: the secant through the two steps with the most different
// winds, when they moved the angle the expected way; kDegreesPerWindStart otherwise.
double degreesPerWind(const std::vector<RainMatchStep>& steps) {
  const auto [low, high] = std::minmax_element(
      steps.begin(), steps.end(), [](const RainMatchStep& a, const RainMatchStep& b) {
        return a.look.windRightMetersPerSecond < b.look.windRightMetersPerSecond;
      });
  const double dWind = high->look.windRightMetersPerSecond - low->look.windRightMetersPerSecond;
  const double dAngle = high->stats.angleDeg - low->stats.angleDeg;
  if (dWind > 0.05 && std::abs(dAngle) > 0.3 && dAngle / dWind < 0.0) return dAngle / dWind;
  return kDegreesPerWindStart;
}

}  // namespace

std::vector<std::string> lookOverrides(const RainLook& look) {
  std::vector<std::string> overrides{fmt::format("rain.rate_mm_h={:.4g}", look.rateMmPerHour),
                                     fmt::format("camera.exposure_s={:.4g}", look.exposureSeconds),
                                     fmt::format("rain.opacity={:.4g}", look.opacity),
                                     fmt::format("rain.far_m={:.4g}", look.farMeters)};
  if (!look.baseWind) {
    overrides.push_back(
        fmt::format("rain.wind.speed_m_s={:.4g}", std::abs(look.windRightMetersPerSecond)));
    overrides.push_back(
        fmt::format("rain.wind.dir_deg={}", look.windRightMetersPerSecond < 0.0 ? 180 : 0));
  }
  return overrides;
}

RainMatch matchRain(const RainMatchSettings& settings, const RenderLook& render) {
  if (settings.steps < 1) throw UsageError("match: at least one step");
  const RealClip clip = readRealClip(settings.clip, settings.frames, settings.widthPx);
  const std::vector<derain::CleanPlate> cleanPlates = cleanPlatesRgb(clip.frames);
  std::vector<cv::Mat3f> plates;
  for (const derain::CleanPlate& plate : cleanPlates) plates.push_back(plate.plate);
  RainMatch match;
  match.clip = clip.name;
  match.reference = measureLayers(clip.frames, cleanPlates);
  if (!(match.reference.streaksPerMpx > 0.0) || !std::isfinite(match.reference.lengthP50Px))
    throw Error(fmt::format("match: {} shows no rain streaks to match (none of {} frames holds a "
                            "streak brighter than its clean plate by 10 codes)",
                            settings.clip, clip.frames.size()),
                {"match", {}, settings.clip});
  // Gauss-Newton steps from the best step so far, the rate, exposure and wind at once through a
  // fixed response (the numbers interact: a longer shutter also dims the streaks and thins them
  // out). A step that does worse halves the next one from the best (a line search).
  match.angleMatched = std::isfinite(match.reference.angleDeg) &&
                       match.reference.angleSpreadDeg <= kMaxMatchedAngleSpreadDeg;
  if (!match.angleMatched)
    log::warning(fmt::format(
        "match: {}'s streaks spread {:.0f} deg around {:.1f} deg (more than {:g}: no clear "
        "direction), so the angle is not matched and the wind stays the base preset's",
        settings.clip, match.reference.angleSpreadDeg, match.reference.angleDeg,
        kMaxMatchedAngleSpreadDeg));
  double share = 1.0;
  RainLook look = settings.start;
  look.baseWind = !match.angleMatched;
  for (int step = 0; step < settings.steps; ++step) {
    const auto started = std::chrono::steady_clock::now();
    RainMatchStep result;
    result.look = look;
    const std::vector<cv::Mat3f> rendered =
        render(plates, clip.fps, clip.filmedWidthPx, lookOverrides(look));
    // Measured as the reference is: against clean plates estimated from the frames themselves
    // (against the plates they were rendered on, the estimator's own error, which the
    // reference's rain carries, would be missing: pluvia's rain of known rate was matched at
    // 0.6 of it).
    result.stats = measureLayers(rendered, cleanPlatesRgb(rendered));
    result.ratios = fittedRatios(result.stats, match.reference);
    std::vector<double> values;
    for (const auto& [name, ratio] : result.ratios) values.push_back(ratio);
    result.typical = derain::typicalFactor(values);
    result.seconds = secondsSince(started);
    log::info(
        fmt::format("match: step {}: rate {:.3g} mm/h, exposure 1/{:.0f} s, drops to {:.3g} m, "
                    "opacity {:.2f}, wind {:+.2f} m/s: typical x{:.2f}",
                    step + 1, look.rateMmPerHour, 1.0 / look.exposureSeconds, look.farMeters,
                    look.opacity, look.windRightMetersPerSecond, result.typical));
    match.steps.push_back(result);
    const bool better = std::isfinite(result.typical) &&
                        (match.steps.size() == 1 ||
                         score(result, match.reference, match.angleMatched) <
                             score(match.steps[match.best], match.reference, match.angleMatched));
    if (better) match.best = match.steps.size() - 1;
    share = better ? 1.0 : 0.5 * share;
    const RainMatchStep& from = match.steps[match.best];
    if (!(from.stats.streaksPerMpx > 0.0)) {
      // Nothing visible: more rain before anything else can be measured.
      look.rateMmPerHour = std::min(300.0, look.rateMmPerHour * kMaxStepFactor);
      continue;
    }
    look = moved(from, match.reference, share, degreesPerWind(match.steps), settings.minFarMeters);
  }
  return match;
}

std::string formatRainMatch(const RainMatch& match) {
  const derain::StreakStats& r = match.reference;
  std::string out = fmt::format(
      "{}: {:.0f} streaks/Mpx, length {:.1f} px, width {:.2f} px, dI p90 {:.1f}, peak p90 {:.1f}, "
      "angle {:.1f} deg (spread {:.0f}{})\n",
      match.clip, r.streaksPerMpx, r.lengthP50Px, r.widthP50Px, r.deltaP90, r.peakP90, r.angleDeg,
      r.angleSpreadDeg, match.angleMatched ? "" : ": not matched, the base's wind kept");
  out += fmt::format("{:>4} {:>9} {:>10} {:>7} {:>8} {:>8} {:>8} {:>7} {:>7} {:>7} {:>7} {:>7}\n",
                     "step", "rate mm/h", "exposure", "far m", "opacity", "wind m/s", "typical",
                     "/Mpx", "length", "dI p90", "peak", "angle");
  for (size_t i = 0; i < match.steps.size(); ++i) {
    const RainMatchStep& s = match.steps[i];
    out += fmt::format(
        "{:>4} {:>9.3g} {:>10} {:>7.3g} {:>8.2f} {:>+8.2f} {:>8.2f} {:>7.0f} {:>7.1f} {:>7.1f} "
        "{:>7.1f} {:>7.1f}{}\n",
        i + 1, s.look.rateMmPerHour, fmt::format("1/{:.0f} s", 1.0 / s.look.exposureSeconds),
        s.look.farMeters, s.look.opacity, s.look.windRightMetersPerSecond, s.typical,
        s.stats.streaksPerMpx, s.stats.lengthP50Px, s.stats.deltaP90, s.stats.peakP90,
        s.stats.angleDeg, i == match.best ? "  <- the match" : "");
  }
  return out;
}

}  // namespace pluvia::lab
