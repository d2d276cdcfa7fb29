#include "derain/stroke_extraction.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "rain/stroke_profile.h"
#include "util/error.h"

namespace pluvia::derain {

struct StrokeCollector::Candidate {
  cv::Mat matte;  // CV_32FC1, upright, peak 1, zero outside the stroke
  double lengthPx = 0.0, widthPx = 0.0, contrast = 0.0, score = 0.0;
  int64_t frame = 0;
  int x = 0, y = 0;  // where in the rotated frame (for a deterministic order)
};

struct StrokeCollector::Frame {
  int64_t frame = 0;
  cv::Mat matte;       // CV_32FC1 in [0, 1], no NaN
  cv::Mat valid;       // CV_8UC1, 255 where solved
  cv::Mat background;  // CV_32FC1: the background's grey; empty: none given
  cv::Mat edges;       // CV_32FC1: its gradient magnitude
  double angleDeg = 0.0;
  double noiseSigma = 0.0;  // the solve's (StrokeCollector::addFrame)
  bool cut = false;
};

namespace {

constexpr int kAtlasMaxWidth = 1024;
constexpr int kAtlasPadding = 2;  // zero texels around every stroke (bilinear, clamp-to-edge)
constexpr int kCropMarginPx = 2;  // soft edge kept around a component's mask
constexpr double kMinMotionResponse = 0.05;  // phase correlation peak taken as camera motion
constexpr double kMaxMotionPx = 12.0;        // between mattes, larger motion: not the camera's
constexpr double kTrimLevel = 0.15;      // a crop ends where its rows fall below this of the peak
constexpr double kTrimSideLevel = 0.05;  // and at its sides where its columns do
constexpr double kMinGap = 0.6;        // a stroke's profile dipping below this inside: two strokes
constexpr double kMisfitScale = 0.01;  // of 1 - fidelity, in the score

// The matte rotated by angleDeg so the rain is vertical, on a canvas that holds the whole
// frame, and the mask of the canvas pixels that lie inside the frame's valid area.
struct Upright {
  cv::Mat matte;     // CV_32FC1
  cv::Mat valid;     // CV_8UC1, 255 inside
  cv::Mat toCanvas;  // 2x3 affine: frame pixel -> canvas pixel
  cv::Mat toSource;  // its inverse
};

Upright rotateUpright(const cv::Mat& matte, const cv::Mat& valid, double angleDeg) {
  // A streak's direction (sin a, -cos a) (frame_stack.h); OpenCV's rotation by +a (counter-
  // clockwise on screen, y down) takes it to (0, -1).
  const double a = angleDeg * M_PI / 180.0;
  const double c = std::abs(std::cos(a)), s = std::abs(std::sin(a));
  const cv::Size size(int(std::ceil(matte.cols * c + matte.rows * s - 1e-6)),
                      int(std::ceil(matte.cols * s + matte.rows * c - 1e-6)));
  cv::Mat m =
      cv::getRotationMatrix2D(cv::Point2f(matte.cols * 0.5f, matte.rows * 0.5f), angleDeg, 1.0);
  m.at<double>(0, 2) += size.width * 0.5 - matte.cols * 0.5;
  m.at<double>(1, 2) += size.height * 0.5 - matte.rows * 0.5;
  Upright out;
  cv::warpAffine(matte, out.matte, m, size, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0.0);
  cv::Mat inside = valid.clone();
  // The frame's own border is an edge too: a stroke running into it is clipped.
  inside.row(0).setTo(0), inside.row(inside.rows - 1).setTo(0);
  inside.col(0).setTo(0), inside.col(inside.cols - 1).setTo(0);
  cv::warpAffine(inside, out.valid, m, size, cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0.0);
  // Bilinear taps near the border mixed in the zeros outside: those pixels are not valid.
  cv::erode(out.valid, out.valid, cv::Mat(), cv::Point(-1, -1), 1);
  out.matte.setTo(0.0f, out.valid == 0);
  out.toCanvas = m;
  cv::invertAffineTransform(m, out.toSource);
  return out;
}

// The matte's own noise level: for a sparse rain matte most pixels are noise, projected onto
// alpha >= 0, so the upper quartile of N(0, s) clipped at 0 is 0.6745 s.
double matteNoise(const cv::Mat& matte, const cv::Mat& valid) {
  std::vector<float> values;
  values.reserve(size_t(matte.total()));
  for (int y = 0; y < matte.rows; ++y) {
    const float* m = matte.ptr<float>(y);
    const uint8_t* v = valid.ptr<uint8_t>(y);
    for (int x = 0; x < matte.cols; ++x)
      if (v[x]) values.push_back(m[x]);
  }
  if (values.empty()) return 0.0;
  const auto q = values.begin() + std::ptrdiff_t(values.size() * 3 / 4);
  std::nth_element(values.begin(), q, values.end());
  return std::max(0.0f, *q) / 0.6745;
}

// The tilt of a crop's alpha-weighted principal axis from the vertical, in the frame_stack.h
// convention (positive when the upper end lies to the right).
double principalTiltDeg(const cv::Mat& crop) {
  const cv::Moments m = cv::moments(crop, false);
  if (m.m00 <= 0.0) return 0.0;
  // mu11 < 0: x grows as y falls, the upper end is to the right.
  return 0.5 * std::atan2(-2.0 * m.mu11, m.mu02 - m.mu20) * 180.0 / M_PI;
}

// The crop turned by tiltDeg about its centre so its axis is vertical, trimmed to what it holds
// plus kCropMarginPx.
cv::Mat straighten(const cv::Mat& crop, double tiltDeg) {
  const int pad = int(std::ceil(0.5 * std::max(crop.cols, crop.rows) *
                                std::sin(std::abs(tiltDeg) * M_PI / 180.0))) +
                  kCropMarginPx;
  cv::Mat padded;
  cv::copyMakeBorder(crop, padded, pad, pad, pad, pad, cv::BORDER_CONSTANT, 0.0);
  const cv::Mat m = cv::getRotationMatrix2D(
      cv::Point2f((padded.cols - 1) * 0.5f, (padded.rows - 1) * 0.5f), tiltDeg, 1.0);
  cv::Mat turned;
  cv::warpAffine(padded, turned, m, padded.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0.0);
  double peak = 0.0;
  cv::minMaxLoc(turned, nullptr, &peak);
  cv::Mat nonzero = turned > 1e-3 * peak;
  const cv::Rect held = cv::boundingRect(nonzero);
  if (held.empty()) return crop;
  const cv::Rect keep = (held + cv::Size(2 * kCropMarginPx, 2 * kCropMarginPx) -
                         cv::Point(kCropMarginPx, kCropMarginPx)) &
                        cv::Rect(0, 0, turned.cols, turned.rows);
  cv::Mat out = turned(keep).clone();
  out.setTo(0.0f, out < 1e-3 * peak);
  return out;
}

// The crop cut down to the stroke, so its atlas rectangle hugs it (the renderer stretches the
// rectangle over the drop's quad): the run of rows around its peak whose peak is at least
// kTrimLevel of the stroke's (a faint tail or a neighbour's end beyond it goes) and a row
// beyond, then the columns that hold anything above kTrimSideLevel.
cv::Mat trimToStroke(const cv::Mat& crop) {
  double peak = 0.0;
  cv::Point at;
  cv::minMaxLoc(crop, nullptr, &peak, nullptr, &at);
  if (peak <= 0.0) return crop;
  auto rowPeak = [&](int y) {
    double v = 0.0;
    cv::minMaxLoc(crop.row(y), nullptr, &v);
    return v;
  };
  int top = at.y, bottom = at.y;
  while (top > 0 && rowPeak(top - 1) >= kTrimLevel * peak) --top;
  while (bottom + 1 < crop.rows && rowPeak(bottom + 1) >= kTrimLevel * peak) ++bottom;
  // One row beyond, so the length's half-maximum crossings stay inside.
  top = std::max(0, top - 1);
  bottom = std::min(crop.rows - 1, bottom + 1);
  cv::Mat rows = crop.rowRange(top, bottom + 1);
  int left = crop.cols, right = -1;
  for (int x = 0; x < crop.cols; ++x) {
    double v = 0.0;
    cv::minMaxLoc(rows.col(x), nullptr, &v);
    if (v >= kTrimSideLevel * peak) left = std::min(left, x), right = std::max(right, x);
  }
  cv::Mat out = rows.colRange(left, right + 1).clone();
  // The rows beyond the run keep only what lies within its columns; a last speck below the
  // side level goes too, so the rectangle holds the stroke and little else.
  out.setTo(0.0f, out < kTrimSideLevel * peak);
  return out;
}

// A streak modelled as a segment of length L whose ends soften as its sides do (a Gaussian of
// sigma s, the drop's own blur): its profile along its length, Phi((x + L/2) / s) -
// Phi((x - L/2) / s), is this long at half its peak.
double segmentLengthPx(double lengthPx, double sigmaPx) {
  lengthPx = std::max(lengthPx, 1e-3);  // a point: 2.355 sigmas
  auto phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  auto profile = [&](double x) {
    return phi((x + 0.5 * lengthPx) / sigmaPx) - phi((x - 0.5 * lengthPx) / sigmaPx);
  };
  const double half = 0.5 * profile(0.0);
  double inside = 0.0, outside = 0.5 * lengthPx + 6.0 * sigmaPx;
  for (int i = 0; i < 50; ++i) {
    const double x = 0.5 * (inside + outside);
    (profile(x) > half ? inside : outside) = x;
  }
  return inside + outside;
}

// The streak's own half-maximum length from that of its matte blurred along it by blurSigmaPx:
// the segment whose ends, softened by the streak's own sigma (its width over 2.355) and the blur
// together, give the measured length, measured with its own sigma alone.
double unblurredLengthPx(double measuredPx, double blurSigmaPx, double widthPx) {
  const double ownSigma = std::max(widthPx, 1e-3) / (2.0 * std::sqrt(2.0 * std::log(2.0)));
  const double blurredSigma = std::hypot(ownSigma, blurSigmaPx);
  if (segmentLengthPx(0.0, blurredSigma) >= measuredPx) return segmentLengthPx(0.0, ownSigma);
  double shorter = 0.0, longer = measuredPx;  // the blur only lengthens it
  for (int i = 0; i < 50; ++i) {
    const double length = 0.5 * (shorter + longer);
    (segmentLengthPx(length, blurredSigma) < measuredPx ? shorter : longer) = length;
  }
  return segmentLengthPx(0.5 * (shorter + longer), ownSigma);
}

struct Measure {
  double lengthPx = 0.0, widthPx = 0.0, contrast = 0.0;
  double bendPx = 0.0;  // RMS distance of the row centres from their straight-line fit
  double fill = 0.0;    // mean row peak over the stroke's length, over its peak (1: even)
  double gap = 0.0;     // lowest row peak over the stroke's length, over its peak
  // Normalised correlation of the crop with an ideal straight streak: its own row peaks times a
  // Gaussian cross-section of its width centred on its fitted axis (1: a clean streak; forks,
  // zigzags, blobs beside it lower it).
  double fidelity = 0.0;
};

// Length and width: the matte's own (rain/stroke_profile.h), as the renderer measures it.
Measure measureStroke(const cv::Mat& crop) {
  Measure m;
  const rain::StrokeProfile profile =
      rain::strokeProfile(crop.ptr<float>(0), crop.step1(), crop.cols, crop.rows);
  m.contrast = profile.contrast;
  if (m.contrast <= 0.0) return m;
  const std::vector<double>& rowPeak = profile.rowPeak;
  const std::vector<double>& rowSum = profile.rowSum;
  const double along = profile.along, half = 0.5 * along;
  const int first = profile.first, last = profile.last;
  m.lengthPx = profile.lengthPx;
  m.widthPx = profile.widthPx;
  double profileSum = 0.0;
  // Gaps: the profile's lowest point inside, away from the ends (where it falls to half).
  const int inset = std::max(1, int(std::lround(0.15 * (last - first))));
  m.gap = 1.0;
  for (int y = first; y <= last; ++y) {
    profileSum += rowSum[size_t(y)];
    if (y >= first + inset && y <= last - inset) m.gap = std::min(m.gap, rowSum[size_t(y)] / along);
  }
  m.fill = profileSum / (double(last - first + 1) * along);
  // Row centres (alpha-weighted) over the same rows, fitted by x = a + b y (weighted).
  double sw = 0, sy = 0, sx = 0, syy = 0, sxy = 0;
  std::vector<std::array<double, 3>> centres;  // y, x, weight
  for (int y = first; y <= last; ++y) {
    if (rowSum[size_t(y)] < half) continue;
    const float* p = crop.ptr<float>(y);
    double xs = 0.0;
    for (int x = 0; x < crop.cols; ++x) xs += double(x) * p[x];
    const double w = rowSum[size_t(y)], xc = xs / w;
    centres.push_back({double(y), xc, w});
    sw += w, sy += w * y, sx += w * xc, syy += w * y * y, sxy += w * y * xc;
  }
  const double det = sw * syy - sy * sy;
  const double b = det > 1e-12 ? (sw * sxy - sy * sx) / det : 0.0;
  const double a = (sx - b * sy) / sw;
  double residual = 0.0;
  for (const auto& [y, x, w] : centres) residual += w * (x - a - b * y) * (x - a - b * y);
  m.bendPx = std::sqrt(residual / sw);
  const double sigma = std::max(m.widthPx / std::sqrt(2.0 * M_PI), 0.3);
  double cross = 0.0, modelEnergy = 0.0, cropEnergy = 0.0;
  for (int y = 0; y < crop.rows; ++y) {
    const float* p = crop.ptr<float>(y);
    const double centre = a + b * y;
    for (int x = 0; x < crop.cols; ++x) {
      const double model =
          rowPeak[size_t(y)] * std::exp(-0.5 * (x - centre) * (x - centre) / (sigma * sigma));
      cross += model * p[x];
      modelEnergy += model * model;
      cropEnergy += double(p[x]) * p[x];
    }
  }
  m.fidelity = cross / std::sqrt(std::max(modelEnergy * cropEnergy, 1e-24));
  return m;
}

// The mean over the rows of `rect` of the largest gradient magnitude in the row: about the
// edge's gradient when an edge runs along the rect, the noise's when the area is flat.
double backgroundEdge(const cv::Mat& edges, cv::Rect rect) {
  if (edges.empty()) return 0.0;
  rect &= cv::Rect(0, 0, edges.cols, edges.rows);
  if (rect.empty()) return 0.0;
  double sum = 0.0;
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    const float* e = edges.ptr<float>(y);
    sum += *std::max_element(e + rect.x, e + rect.x + rect.width);
  }
  return sum / rect.height;
}

// The frame pixels under a canvas rectangle: the bounding box of its corners mapped back.
cv::Rect sourceRect(const cv::Rect& canvas, const cv::Mat& toSource) {
  std::vector<cv::Point2f> corners = {
      cv::Point2f(float(canvas.x), float(canvas.y)),
      cv::Point2f(float(canvas.x + canvas.width), float(canvas.y)),
      cv::Point2f(float(canvas.x), float(canvas.y + canvas.height)),
      cv::Point2f(float(canvas.x + canvas.width), float(canvas.y + canvas.height))};
  cv::transform(corners, corners, toSource);
  return cv::boundingRect(corners);
}

// How much of the matte under `rect` one of the other mattes holds too, shifted by up to
// `radius` pixels: 1 - (least squared difference) / (patch energy). 1: the same pattern at the
// same strength, 0 (or less): nothing like it there.
double staticShare(const cv::Mat& matte, const std::vector<cv::Mat>& others, cv::Rect rect,
                   int radius) {
  const cv::Rect frame(0, 0, matte.cols, matte.rows);
  rect &= frame;
  if (others.empty() || rect.empty()) return 0.0;
  const cv::Mat patch = matte(rect);
  const double energy = patch.dot(patch);
  if (energy <= 0.0) return 0.0;
  const cv::Rect search =
      (rect + cv::Size(2 * radius, 2 * radius) - cv::Point(radius, radius)) & frame;
  double best = 0.0;
  for (const cv::Mat& other : others) {
    cv::Mat difference;
    cv::matchTemplate(other(search), patch, difference, cv::TM_SQDIFF);
    double least = 0.0;
    cv::minMaxLoc(difference, &least);
    best = std::max(best, 1.0 - std::max(least, 0.0) / energy);
  }
  return best;
}

// The shift that aligns `from` onto `to` (phase correlation); zero when its peak is weak, or
// farther than maxPx.
cv::Point2d cameraShift(const cv::Mat& from, const cv::Mat& to, double maxPx) {
  cv::Mat window;
  cv::createHanningWindow(window, to.size(), CV_32F);
  double response = 0.0;
  // Copies: OpenCV multiplies the window into its inputs in place when their size needs no
  // padding.
  const cv::Point2d shift = cv::phaseCorrelate(from.clone(), to.clone(), window, &response);
  if (!(response >= kMinMotionResponse) || std::hypot(shift.x, shift.y) > maxPx) return {};
  return shift;
}

// The blurred matte of the other components (labels but `label`) in `box` grown by `marginPx`.
double otherEnergy(const cv::Mat& labels, const cv::Mat& blurred, int label, const cv::Rect& box,
                   int marginPx) {
  const cv::Rect around =
      (box + cv::Size(2 * marginPx, 2 * marginPx) - cv::Point(marginPx, marginPx)) &
      cv::Rect(0, 0, labels.cols, labels.rows);
  double other = 0.0;
  for (int y = around.y; y < around.y + around.height; ++y) {
    const int* l = labels.ptr<int>(y);
    const float* b = blurred.ptr<float>(y);
    for (int x = around.x; x < around.x + around.width; ++x)
      if (l[x] && l[x] != label) other += b[x];
  }
  return other;
}

}  // namespace

StrokeCollector::StrokeCollector(StrokeExtractionSettings settings) : settings_(settings) {
  if (settings_.count < 1) throw Error("stroke extraction: count must be at least 1");
}
StrokeCollector::~StrokeCollector() = default;
StrokeCollector::StrokeCollector(StrokeCollector&&) noexcept = default;
StrokeCollector& StrokeCollector::operator=(StrokeCollector&&) noexcept = default;

size_t StrokeCollector::candidateCount() const {
  return accepted_;
}

void StrokeCollector::addFrame(int64_t frame, const cv::Mat& matte, double angleDeg,
                               double noiseSigma, const cv::Mat& background, const cv::Mat& valid) {
  if (matte.empty()) return;
  if (matte.type() != CV_32FC1)
    throw Error("stroke extraction: the matte must be CV_32FC1", {"strokes", frame, {}});
  if (!valid.empty() && (valid.size() != matte.size() || valid.type() != CV_8UC1))
    throw Error("stroke extraction: the valid mask must be CV_8UC1 of the matte's size",
                {"strokes", frame, {}});
  Frame f;
  f.frame = frame;
  f.angleDeg = angleDeg;
  f.matte = matte.clone();
  cv::patchNaNs(f.matte, 0.0);
  f.matte = cv::max(cv::min(f.matte, 1.0f), 0.0f);
  f.valid = valid.empty() ? cv::Mat(matte.size(), CV_8UC1, cv::Scalar(255)) : (valid != 0);
  if (!background.empty()) {
    if (background.size() != matte.size() ||
        (background.type() != CV_32FC3 && background.type() != CV_32FC1))
      throw Error(
          "stroke extraction: the background must be CV_32FC3 or CV_32FC1 of the matte's size",
          {"strokes", frame, {}});
    cv::Mat& gray = f.background;
    if (background.channels() == 3)
      cv::transform(background, gray, cv::Matx13f(1.0f / 3, 1.0f / 3, 1.0f / 3));
    else
      gray = background.clone();
    cv::patchNaNs(gray, 0.0);
    cv::Mat dx, dy;
    cv::Sobel(gray, dx, CV_32F, 1, 0, 3, 1.0 / 8.0);
    cv::Sobel(gray, dy, CV_32F, 0, 1, 3, 1.0 / 8.0);
    cv::magnitude(dx, dy, f.edges);
  }
  f.noiseSigma = noiseSigma;
  // A neighbour of another size (another clip) is no neighbour.
  if (!recent_.empty() && recent_.back().matte.size() != f.matte.size()) {
    if (!recent_.back().cut) {
      std::vector<const Frame*> before;
      if (recent_.size() >= 2) before.push_back(&recent_[recent_.size() - 2]);
      cut(recent_.back(), before);
    }
    recent_.clear();
  }
  recent_.push_back(std::move(f));
  if (recent_.size() == 2 && !recent_[0].cut) {
    cut(recent_[0], {&recent_[1]});
    recent_[0].cut = true;
  }
  if (recent_.size() == 3) {
    cut(recent_[1], {&recent_[0], &recent_[2]});
    recent_[1].cut = true;
    recent_.erase(recent_.begin());
  }
}

void StrokeCollector::cut(const Frame& f, const std::vector<const Frame*>& neighbours) {
  const int64_t frame = f.frame;
  const cv::Mat& clean = f.matte;
  const Upright up = rotateUpright(clean, f.valid, f.angleDeg);

  // The neighbours' mattes with the camera's motion between them and this frame undone: the
  // motion from the backgrounds where both frames have one (no rain falls there to be taken for
  // the camera, so a fast pan is followed: rb2's 24 px a frame); else from the mattes, which
  // static structure dominates, up to kMaxMotionPx (farther is rain falling: the same drops a
  // frame later).
  std::vector<cv::Mat> aligned;
  for (const Frame* n : neighbours) {
    const bool backgrounds = !f.background.empty() && !n->background.empty();
    const cv::Point2d shift = backgrounds ? cameraShift(n->background, f.background, INFINITY)
                                          : cameraShift(n->matte, clean, kMaxMotionPx);
    cv::Mat moved;
    cv::warpAffine(n->matte, moved, cv::Matx23d(1, 0, shift.x, 0, 1, shift.y), clean.size(),
                   cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0.0);
    aligned.push_back(moved);
  }

  // The blur along the rain (vertical on the upright canvas) smooths the streaks along their
  // length only; the threshold stands above the blurred matte's noise, which the blur lowers by
  // the root of the kernel's sum of squares.
  cv::Mat blurred;
  const int radius = std::max(1, int(std::ceil(3.0 * settings_.blurSigmaPx)));
  const cv::Mat kernel = cv::getGaussianKernel(2 * radius + 1, settings_.blurSigmaPx, CV_32F);
  cv::filter2D(up.matte, blurred, CV_32F, kernel, cv::Point(-1, -1), 0.0, cv::BORDER_CONSTANT);
  blurred.setTo(0.0f, up.valid == 0);
  const double noise =
      std::max(f.noiseSigma * std::sqrt(kernel.dot(kernel)), matteNoise(blurred, up.valid));
  const double threshold = std::max(settings_.noiseFactor * noise, settings_.minContrast);

  cv::Mat labels, stats, centroids;
  const cv::Mat mask = blurred > threshold;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  if (n <= 1) return;

  // Components that reach the edge zone: within a pixel of the frame's (rotated) valid area.
  cv::Mat edgeZone;
  cv::dilate(up.valid == 0, edgeZone, cv::Mat(), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, 255);
  std::vector<uint8_t> touchesEdge(size_t(n), 0);
  std::vector<double> energy(size_t(n), 0.0);
  for (int y = 0; y < labels.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    const uint8_t* e = edgeZone.ptr<uint8_t>(y);
    const float* b = blurred.ptr<float>(y);
    for (int x = 0; x < labels.cols; ++x) {
      if (!l[x]) continue;
      if (e[x]) touchesEdge[size_t(l[x])] = 1;
      energy[size_t(l[x])] += b[x];
    }
  }

  const cv::Mat grow = cv::getStructuringElement(
      cv::MORPH_ELLIPSE, cv::Size(2 * kCropMarginPx + 1, 2 * kCropMarginPx + 1));
  for (int label = 1; label < n; ++label) {
    if (touchesEdge[size_t(label)]) continue;
    const cv::Rect box(
        stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
        stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
    if (box.height < settings_.minLengthPx) continue;  // cheap test before cropping

    // The crop: the blurred matte around the component, other components and anything further
    // than kCropMarginPx from this one set to zero.
    const cv::Rect cropBox = (box + cv::Size(2 * kCropMarginPx, 2 * kCropMarginPx) -
                              cv::Point(kCropMarginPx, kCropMarginPx)) &
                             cv::Rect(0, 0, labels.cols, labels.rows);
    cv::Mat own = labels(cropBox) == label, near;
    cv::dilate(own, near, grow, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, 0);
    near &= (labels(cropBox) == label) | (labels(cropBox) == 0);
    cv::Mat crop = cv::Mat::zeros(cropBox.size(), CV_32FC1);
    blurred(cropBox).copyTo(crop, near);

    // The stroke's contrast: the frame's own matte at the peak (rotation and blur soften a
    // thin streak's peak), the largest value within a pixel of where the crop peaks.
    cv::Point peakAt;
    cv::minMaxLoc(crop, nullptr, nullptr, nullptr, &peakAt);
    const cv::Point2d canvas(peakAt.x + cropBox.x, peakAt.y + cropBox.y);
    const cv::Mat& t = up.toSource;
    const cv::Point source(int(std::lround(t.at<double>(0, 0) * canvas.x +
                                           t.at<double>(0, 1) * canvas.y + t.at<double>(0, 2))),
                           int(std::lround(t.at<double>(1, 0) * canvas.x +
                                           t.at<double>(1, 1) * canvas.y + t.at<double>(1, 2))));
    double contrast = 0.0;
    const cv::Rect near3 =
        cv::Rect(source.x - 1, source.y - 1, 3, 3) & cv::Rect(0, 0, clean.cols, clean.rows);
    if (!near3.empty()) cv::minMaxLoc(clean(near3), nullptr, &contrast);

    // Its own axis: close to the rain's, then turned exactly upright.
    const double tilt = principalTiltDeg(crop);
    if (std::abs(tilt) > settings_.maxTiltDeg) continue;
    if (std::abs(tilt) > 0.25) crop = straighten(crop, tilt);

    crop = trimToStroke(crop);
    const Measure m = measureStroke(crop);
    const double ownLengthPx = unblurredLengthPx(m.lengthPx, settings_.blurSigmaPx, m.widthPx);
    if (m.contrast <= threshold || ownLengthPx < settings_.minLengthPx) continue;
    if (m.widthPx <= 0.0 || ownLengthPx < settings_.minAspect * m.widthPx) continue;
    if (m.bendPx > settings_.maxBendPx) continue;
    if (m.gap < kMinGap) continue;  // two strokes end to end, or one broken by noise
    if (m.fidelity < settings_.minFidelity) continue;

    // On an edge of the scene: the background's gradient along the stroke.
    const double edge = backgroundEdge(f.edges, sourceRect(cropBox, up.toSource));
    if (edge > settings_.maxBackgroundEdge * std::max(contrast, m.contrast)) continue;

    // Static structure: the same pattern in a neighbouring frame, near the same place.
    const double held =
        staticShare(clean, aligned, sourceRect(cropBox, up.toSource), settings_.staticTolerancePx);
    if (held > settings_.maxStaticShare) continue;

    // Isolation: the stroke's share of the matte energy (of thresholded components) in its box
    // grown by isolationMarginPx: 1 alone, 1/2 with as much other rain around it.
    const double isolation =
        energy[size_t(label)] / (energy[size_t(label)] + otherEnergy(labels, blurred, label, box,
                                                                     settings_.isolationMarginPx));

    Candidate c;
    c.matte = crop / m.contrast;
    c.lengthPx = m.lengthPx;
    c.widthPx = m.widthPx;
    c.contrast = std::max(contrast, m.contrast);
    c.frame = frame;
    c.x = box.x, c.y = box.y;
    // score = contrast * sqrt(length * aspect) * isolation^2 * fill^2
    //         * exp(-(1 - fidelity) / kMisfitScale),   aspect = length / width:
    // brighter, longer, thinner, lonelier, more even along its length and closer to a clean
    // straight streak is better. The square root keeps a long streak from outranking a much
    // clearer short one; the squares make strokes crowded by others (a cut that holds part of a
    // neighbour) or lumpy along their length (two drops end to end, compression blocks) rank
    // well below clean ones; each 0.01 of misfit (forks, zigzags) costs a factor e.
    c.score = c.contrast * m.lengthPx / std::sqrt(std::max(m.widthPx, 1.0)) * isolation *
              isolation * m.fill * m.fill * std::exp(-(1.0 - m.fidelity) / kMisfitScale);
    candidates_.push_back(std::move(c));
    ++accepted_;
  }

  // Keep memory bounded over long clips: only the best few times `count` can ever be chosen.
  const size_t keep = size_t(settings_.count) * 4 + 256;
  if (candidates_.size() > 2 * keep) {
    std::nth_element(candidates_.begin(), candidates_.begin() + std::ptrdiff_t(keep),
                     candidates_.end(),
                     [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    candidates_.resize(keep);
  }
}

rain::StrokeLibrary StrokeCollector::finish() {
  if (!recent_.empty() && !recent_.back().cut) {
    std::vector<const Frame*> neighbours;
    if (recent_.size() >= 2) neighbours.push_back(&recent_[recent_.size() - 2]);
    cut(recent_.back(), neighbours);
    recent_.back().cut = true;
  }

  std::vector<const Candidate*> best;
  for (const auto& c : candidates_) best.push_back(&c);
  std::sort(best.begin(), best.end(), [](const Candidate* a, const Candidate* b) {
    if (a->score != b->score) return a->score > b->score;
    if (a->frame != b->frame) return a->frame < b->frame;
    return std::make_pair(a->y, a->x) < std::make_pair(b->y, b->x);
  });
  if (best.size() > size_t(settings_.count)) best.resize(size_t(settings_.count));

  rain::StrokeLibrary library;
  if (best.empty()) return library;

  // Shelf packing: tallest first, rows left to right, kAtlasPadding zero texels between strokes
  // and around the atlas' border. The width aims at a square atlas, at most kAtlasMaxWidth.
  std::vector<size_t> order(best.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return best[a]->matte.rows > best[b]->matte.rows; });
  double area = 0.0;
  int widest = 0;
  for (const Candidate* c : best) {
    area += double(c->matte.cols + kAtlasPadding) * double(c->matte.rows + kAtlasPadding);
    widest = std::max(widest, c->matte.cols + 2 * kAtlasPadding);
  }
  const int width = std::min(
      kAtlasMaxWidth, std::max(widest, int(std::ceil(std::sqrt(area * 1.1))) + kAtlasPadding));
  if (widest > kAtlasMaxWidth) throw Error("stroke extraction: a stroke is wider than the atlas");

  std::vector<cv::Point> at(best.size());
  int x = kAtlasPadding, y = kAtlasPadding, shelf = 0, usedWidth = 0;
  for (size_t i : order) {
    const cv::Mat& m = best[i]->matte;
    if (x + m.cols + kAtlasPadding > width) {
      x = kAtlasPadding;
      y += shelf + kAtlasPadding;
      shelf = 0;
    }
    at[i] = {x, y};
    x += m.cols + kAtlasPadding;
    usedWidth = std::max(usedWidth, x);
    shelf = std::max(shelf, m.rows);
  }
  const int height = y + shelf + kAtlasPadding;

  cv::Mat atlas = cv::Mat::zeros(height, usedWidth, CV_32FC1);
  for (size_t i = 0; i < best.size(); ++i) {
    const Candidate& c = *best[i];
    c.matte.copyTo(atlas(cv::Rect(at[i], c.matte.size())));
    rain::StrokeInfo info;
    info.x = at[i].x, info.y = at[i].y, info.width = c.matte.cols, info.height = c.matte.rows;
    info.lengthPx = c.lengthPx;
    info.widthPx = c.widthPx;
    info.contrast = c.contrast;
    info.sourceFrame = c.frame;
    info.score = c.score;
    library.strokes.push_back(info);
    library.atlas.rects.push_back(
        {float(info.x), float(info.y), float(info.x + info.width), float(info.y + info.height)});
  }
  library.atlas.width = atlas.cols;
  library.atlas.height = atlas.rows;
  library.atlas.alpha.assign(atlas.begin<float>(), atlas.end<float>());
  return library;
}

ClipStrokes cutStrokesFromClip(const std::string& input, const ClipDerainSettings& clip,
                               const StrokeExtractionSettings& extraction) {
  auto cutAll = [&](const ClipDerainSettings& settings, ClipDerainSummary& summary) {
    StrokeCollector collector(extraction);
    ClipStrokes out;
    summary = derainClip(input, settings, [&](const ClipDerainFrame& frame) {
      ++out.frames;
      // Where no window has seen the rain's direction the mattes were solved and would be cut
      // along the solver's vertical start: what lies along it in real mattes is the scene's
      // vertical edges the registration left (window mullions, tree trunks, pillars), not rain.
      if (!frame.angleFound && !frame.angleCarried) return;
      ++out.framesCut;
      collector.addFrame(frame.frame, frame.matte, frame.angleDeg, frame.noiseSigma, frame.clean,
                         frame.covered);
    });
    out.library = collector.finish();
    out.candidates = collector.candidateCount();
    return out;
  };
  ClipDerainSummary summary;
  ClipStrokes out = cutAll(clip, summary);
  // Windows before the first one that saw the direction were not cut: solve and cut the clip
  // again with the direction the later windows found as every window's start.
  if (out.framesCut < out.frames && summary.windowsWithAngle > 0) {
    ClipDerainSettings again = clip;
    again.knownAngleDeg = summary.angleDeg;
    ClipDerainSummary second;
    ClipStrokes all = cutAll(again, second);
    if (all.candidates > out.candidates) out = std::move(all), summary = second;
  }
  out.angleDeg = summary.angleDeg;
  out.angleDescription = describeRainAngle(summary);
  return out;
}

}  // namespace pluvia::derain
