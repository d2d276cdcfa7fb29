#include "lab/rain_match.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "lab/real_rain_clip.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia::lab {
namespace {

// Visible streak length grows about as exposure^kLengthExponent (measured on NTURain's plates:
// 3.1, 4.0 and 5.1 px at 1/1000, 1/500 and 1/250 s).
constexpr double kLengthExponent = 0.4;
// Streak angle per m/s of wind across the view before two steps give the secant: a 4.5 m/s fall.
constexpr double kDegreesPerWindStart = -180.0 / M_PI / 4.5;
// No step moves a number by more than this factor.
constexpr double kMaxStepFactor = 3.0;
// The first step goes this share of the way the model asks for (in log terms).
constexpr double kFirstDamping = 0.5;

double clampedFactor(double factor) {
  if (!std::isfinite(factor) || factor <= 0.0) return 1.0;
  return std::clamp(factor, 1.0 / kMaxStepFactor, kMaxStepFactor);
}

// The three numbers a step moves, one at a time (the wind moves every step, with the angle).
enum class Knob { exposure, rate, opacity };
constexpr Knob kKnobs[] = {Knob::exposure, Knob::rate, Knob::opacity};
// The match weighs the angle beside the typical factor (which leaves it out): a step's score is
// typical * exp(|angle error| / kAngleScaleDeg).
constexpr double kAngleScaleDeg = 10.0;

double score(const RainMatchStep& step, const derain::StreakStats& target) {
  const double angleError = std::abs(step.stats.angleDeg - target.angleDeg);
  return step.typical * (std::isfinite(angleError) ? std::exp(angleError / kAngleScaleDeg) : 1.0);
}

// `from`'s look with one number moved the way the streak model asks, by the model's factor to the
// power `damping` (negative: the other way), and the wind corrected for the angle.
RainLook moved(const RainMatchStep& from, const derain::StreakStats& target, Knob knob,
               double damping, double degreesPerWind) {
  const derain::StreakStats& s = from.stats;
  RainLook look = from.look;
  const auto scale = [&](double& value, double factor, double lo, double hi) {
    value = std::clamp(value * std::pow(clampedFactor(factor), damping), lo, hi);
  };
  switch (knob) {
    case Knob::exposure:
      scale(look.exposureSeconds,
            std::pow(target.lengthP50Px / s.lengthP50Px, 1.0 / kLengthExponent), 1e-4, 0.5);
      break;
    case Knob::rate:
      scale(look.rateMmPerHour, target.streaksPerMpx / s.streaksPerMpx, 0.1, 300.0);
      break;
    case Knob::opacity:
      scale(look.opacity, std::sqrt((target.deltaP90 / s.deltaP90) * (target.peakP90 / s.peakP90)),
            0.1, 8.0);
      break;
  }
  if (std::isfinite(target.angleDeg) && std::isfinite(s.angleDeg))
    look.windRightMetersPerSecond =
        std::clamp(look.windRightMetersPerSecond + (target.angleDeg - s.angleDeg) / degreesPerWind,
                   -15.0, 15.0);
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
  return {fmt::format("rain.rate_mm_h={:.4g}", look.rateMmPerHour),
          fmt::format("camera.exposure_s={:.4g}", look.exposureSeconds),
          fmt::format("rain.opacity={:.4g}", look.opacity),
          fmt::format("rain.wind.speed_m_s={:.4g}", std::abs(look.windRightMetersPerSecond)),
          fmt::format("rain.wind.dir_deg={}", look.windRightMetersPerSecond < 0.0 ? 180 : 0)};
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
  // A coordinate search from the best step so far, one number per step in turn: a move that does
  // better is kept and that number's next move goes further; one that does worse makes its next
  // move half as far the other way (the numbers interact: a longer shutter also dims the streaks,
  // so the model's way is not always better).
  std::array<double, 3> damping;
  damping.fill(kFirstDamping);
  RainLook look = settings.start;
  size_t knob = 0;
  for (int step = 0; step < settings.steps; ++step) {
    const auto started = std::chrono::steady_clock::now();
    RainMatchStep result;
    result.look = look;
    const std::vector<cv::Mat3f> rendered = render(plates, clip.fps, lookOverrides(look));
    // Measured as the reference is: against clean plates estimated from the frames themselves
    // (against the plates they were rendered on, the estimator's own error, which the
    // reference's rain carries, would be missing: pluvia's rain of known rate was matched at
    // 0.6 of it).
    result.stats = measureLayers(rendered, cleanPlatesRgb(rendered));
    result.ratios = derain::ratiosToReal(result.stats, match.reference);
    std::vector<double> values;
    for (const auto& [name, ratio] : result.ratios) values.push_back(ratio);
    result.typical = derain::typicalFactor(values);
    result.seconds = secondsSince(started);
    log::info(
        fmt::format("match: step {}: rate {:.3g} mm/h, exposure 1/{:.0f} s, opacity {:.2f}, "
                    "wind {:+.2f} m/s: typical x{:.2f}",
                    step + 1, look.rateMmPerHour, 1.0 / look.exposureSeconds, look.opacity,
                    look.windRightMetersPerSecond, result.typical));
    match.steps.push_back(result);
    const bool better =
        std::isfinite(result.typical) &&
        (match.steps.size() == 1 || result.typical < match.steps[match.best].typical);
    if (step > 0) damping[knob] *= better ? 1.5 : -0.5;
    if (better) match.best = match.steps.size() - 1;
    const RainMatchStep& from = match.steps[match.best];
    if (!(from.stats.streaksPerMpx > 0.0)) {
      // Nothing visible: more and brighter rain before anything else can be measured.
      look.rateMmPerHour = std::min(300.0, look.rateMmPerHour * kMaxStepFactor);
      look.opacity = std::min(8.0, look.opacity * 2.0);
      continue;
    }
    knob = step == 0 ? 0 : (knob + 1) % 3;
    look = moved(from, match.reference, kKnobs[knob], damping[knob], degreesPerWind(match.steps));
  }
  return match;
}

std::string formatRainMatch(const RainMatch& match) {
  const derain::StreakStats& r = match.reference;
  std::string out = fmt::format(
      "{}: {:.0f} streaks/Mpx, length {:.1f} px, width {:.2f} px, dI p90 {:.1f}, peak p90 {:.1f}, "
      "angle {:.1f} deg\n",
      match.clip, r.streaksPerMpx, r.lengthP50Px, r.widthP50Px, r.deltaP90, r.peakP90, r.angleDeg);
  out += fmt::format("{:>4} {:>9} {:>10} {:>8} {:>8} {:>8} {:>7} {:>7} {:>7} {:>7} {:>7}\n", "step",
                     "rate mm/h", "exposure", "opacity", "wind m/s", "typical", "/Mpx", "length",
                     "dI p90", "peak", "angle");
  for (size_t i = 0; i < match.steps.size(); ++i) {
    const RainMatchStep& s = match.steps[i];
    out += fmt::format(
        "{:>4} {:>9.3g} {:>10} {:>8.2f} {:>+8.2f} {:>8.2f} {:>7.0f} {:>7.1f} {:>7.1f} {:>7.1f} "
        "{:>7.1f}{}\n",
        i + 1, s.look.rateMmPerHour, fmt::format("1/{:.0f} s", 1.0 / s.look.exposureSeconds),
        s.look.opacity, s.look.windRightMetersPerSecond, s.typical, s.stats.streaksPerMpx,
        s.stats.lengthP50Px, s.stats.deltaP90, s.stats.peakP90, s.stats.angleDeg,
        i == match.best ? "  <- the match" : "");
  }
  return out;
}

}  // namespace pluvia::lab
