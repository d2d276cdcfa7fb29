// Synthetic rain with a known answer. Everything here is drawn from first principles and shares
// no code with the solver (not even the angle convention's helpers), so that a bug in one cannot
// hide the same bug in the other.
#include "lab/synthetic_rain.h"

#include <algorithm>
#include <cmath>

#include "util/error.h"
#include "util/hash.h"
#include "util/parallel.h"

namespace pluvia::lab {

using namespace pluvia::derain;  // what this file measures
namespace {

// Random streams: one per frame, split by purpose so that changing e.g. the noise level leaves
// the streaks of the same seed where they were.
constexpr uint64_t kStreakStream = 0x5354524b;  // "STRK"
constexpr uint64_t kColourStream = 0x434f4c52;  // "COLR"
constexpr uint64_t kNoiseStream = 0x4e4f4953;   // "NOIS"

double uniformIn(CounterRng& rng, double lo, double hi) {
  return lo + (hi - lo) * rng.uniform();
}

// Standard normal pairs by Box-Muller (portable, unlike std::normal_distribution).
class Gaussian {
 public:
  explicit Gaussian(CounterRng rng) : rng_(rng) {}
  double next() {
    if (hasSpare_) {
      hasSpare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - rng_.uniform();  // (0, 1]
    const double u2 = rng_.uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * M_PI * u2);
    hasSpare_ = true;
    return r * std::cos(2.0 * M_PI * u2);
  }

 private:
  CounterRng rng_;
  double spare_ = 0.0;
  bool hasSpare_ = false;
};

struct Streak {
  double cx, cy;  // centre, pixel coordinates (pixel (x, y) has its centre at (x, y))
  double length;  // between the two end points of the axis
  double width;   // full width of the solid core
  double peak;    // opacity at the streak's brightest point
};

// Draws one streak into `transmission` (CV_32FC1, the product of (1 - a) of the streaks so far).
// Across the streak the coverage is a box of the streak's width filtered by a one-pixel box
// (1 inside width/2 - 1/2 of the axis, linear to 0 at width/2 + 1/2), measured as the distance
// to the axis segment, so the ends are rounded the same way. Along the streak the opacity ramps
// from half its peak at the upper end to the peak at the lower end (the leading end of a falling
// drop, where it spends the last of the exposure).
void drawStreak(cv::Mat& transmission, const Streak& s, double dx, double dy) {
  const double half = 0.5 * s.length;
  const double ax = s.cx - dx * half, ay = s.cy - dy * half;  // lower end (d points up)
  const double reach = 0.5 * s.width + 0.5;
  const int x0 = std::max(0, int(std::floor(std::min(ax, ax + dx * s.length) - reach)));
  const int x1 =
      std::min(transmission.cols - 1, int(std::ceil(std::max(ax, ax + dx * s.length) + reach)));
  const int y0 = std::max(0, int(std::floor(std::min(ay, ay + dy * s.length) - reach)));
  const int y1 =
      std::min(transmission.rows - 1, int(std::ceil(std::max(ay, ay + dy * s.length) + reach)));
  for (int y = y0; y <= y1; ++y) {
    float* row = transmission.ptr<float>(y);
    for (int x = x0; x <= x1; ++x) {
      const double px = x - ax, py = y - ay;
      const double along = px * dx + py * dy;  // 0 at the lower end, length at the upper end
      const double t = std::clamp(along, 0.0, s.length);
      const double ex = px - t * dx, ey = py - t * dy;
      const double distance = std::sqrt(ex * ex + ey * ey);
      const double coverage = std::clamp(reach - distance, 0.0, 1.0);
      if (coverage <= 0.0) continue;
      const double ramp = 1.0 - 0.5 * t / s.length;
      const double a = s.peak * ramp * coverage;
      row[x] = float(double(row[x]) * (1.0 - a));
    }
  }
}

}  // namespace

SyntheticRain makeSyntheticRain(const cv::Mat& background, const SyntheticRainSettings& settings) {
  return makeSyntheticRainOver(
      std::vector<cv::Mat>(size_t(std::max(settings.frames, 0)), background), settings);
}

SyntheticRain makeSyntheticRainOver(const std::vector<cv::Mat>& backgrounds,
                                    const SyntheticRainSettings& settings) {
  if (backgrounds.empty() || int(backgrounds.size()) != settings.frames)
    throw Error("synthetic rain: one background per frame");
  for (const cv::Mat& background : backgrounds)
    if (background.empty() || background.type() != CV_32FC3 ||
        background.size() != backgrounds.front().size())
      throw Error("synthetic rain: the backgrounds must be non-empty CV_32FC3 images of one size");
  const cv::Mat& background = backgrounds.front();
  if (settings.frames < 1 || settings.minLengthPx <= 0.0 ||
      settings.maxLengthPx < settings.minLengthPx || settings.minWidthPx <= 0.0 ||
      settings.maxWidthPx < settings.minWidthPx || settings.minAlpha < 0.0 ||
      settings.maxAlpha > 1.0 || settings.maxAlpha < settings.minAlpha ||
      settings.streaksPerMegapixel < 0.0 || settings.noiseSigma < 0.0) {
    throw Error("synthetic rain: invalid settings (counts, lengths, widths or opacities)");
  }
  SyntheticRain out;
  out.background = background.clone();
  for (const cv::Mat& each : backgrounds) out.backgrounds.push_back(each.clone());
  // The angle folded into (-90, 90].
  out.angleDeg = settings.angleDeg - 180.0 * std::ceil((settings.angleDeg - 90.0) / 180.0);
  const double radians = settings.angleDeg * M_PI / 180.0;
  // From the lower end to the upper end, x right and y down.
  const double dx = std::sin(radians), dy = -std::cos(radians);

  const int n = settings.frames;
  const int width = background.cols, height = background.rows;
  const long streaks =
      std::lround(settings.streaksPerMegapixel * double(width) * double(height) * 1e-6);
  out.stack.frames.resize(size_t(n));
  out.alpha.resize(size_t(n));
  out.rainColor.resize(size_t(n));

  forEachIndex(n, [&](int k) {
    const uint64_t frameKey = mix64(settings.seed) ^ uint64_t(k);
    CounterRng streakRng(frameKey, kStreakStream), colourRng(frameKey, kColourStream);
    cv::Vec3f colour;
    for (int c = 0; c < 3; ++c)
      colour[c] = float(double(settings.rainColor[c]) * uniformIn(colourRng, 0.97, 1.03));

    cv::Mat transmission(height, width, CV_32FC1, cv::Scalar(1.0f));
    for (long i = 0; i < streaks; ++i) {
      Streak s;
      s.length = uniformIn(streakRng, settings.minLengthPx, settings.maxLengthPx);
      s.width = uniformIn(streakRng, settings.minWidthPx, settings.maxWidthPx);
      s.peak = uniformIn(streakRng, settings.minAlpha, settings.maxAlpha);
      // Centres over the image grown by half a streak, so streaks cross the border as often as
      // they would in a real frame and the density is even up to the edges.
      const double margin = 0.5 * s.length;
      s.cx = uniformIn(streakRng, -margin, width - 1 + margin);
      s.cy = uniformIn(streakRng, -margin, height - 1 + margin);
      drawStreak(transmission, s, dx, dy);
    }
    cv::Mat alpha = 1.0f - transmission;  // over-compositing streaks of one colour

    Gaussian noise(CounterRng(frameKey, kNoiseStream));
    const float sigma = float(settings.noiseSigma);
    cv::Mat frame(height, width, CV_32FC3);
    for (int y = 0; y < height; ++y) {
      const cv::Vec3f* s = backgrounds[size_t(k)].ptr<cv::Vec3f>(y);
      const float* a = alpha.ptr<float>(y);
      cv::Vec3f* o = frame.ptr<cv::Vec3f>(y);
      for (int x = 0; x < width; ++x) {
        for (int c = 0; c < 3; ++c) {
          float v = (1.0f - a[x]) * s[x][c] + a[x] * colour[c];
          if (sigma > 0.0f) v += sigma * float(noise.next());
          o[x][c] = std::clamp(v, 0.0f, 1.0f);
        }
      }
    }
    out.stack.frames[size_t(k)] = frame;
    out.alpha[size_t(k)] = alpha;
    out.rainColor[size_t(k)] = colour;
  });
  return out;
}

}  // namespace pluvia::lab
