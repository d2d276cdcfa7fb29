// `pluvia report derain`: rain extraction against synthetic ground truth, error against run
// time, and convergence on real panning footage (derain_report.h says what is measured).
#include "lab/derain_report.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "derain/rain_direction.h"
#include "derain/registration.h"
#include "image/image_metrics.h"
#include "image/luminance.h"
#include "io/clip_reader.h"
#include "lab/parallax_clip.h"
#include "lab/real_rain_clip.h"
#include "lab/report_numbers.h"
#include "lab/synthetic_rain.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia::lab {

using namespace pluvia::derain;  // what this file measures
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kSweepAngleDeg = 12.0;  // the angle of the case the sweeps (b) run on
constexpr float kMatteViewGain = 4.0f;   // mattes are written x4 (clamped) to be visible
const char* const kRealFootage = "rain_real/nturain_ra1_real_rain_panning";

struct Plan {
  cv::Size size;
  std::vector<double> angles;
  std::vector<int> iterations;
  std::vector<int> windows;
  bool real = true;
};

Plan planFor(const DerainReportSettings& settings) {
  if (settings.quick) return {{320, 240}, {kSweepAngleDeg}, {0, 1, 2}, {5, settings.frames}, false};
  std::vector<int> windows;
  for (int w : {3, 5, 10, 20}) {
    if (w < settings.frames) windows.push_back(w);
  }
  windows.push_back(settings.frames);
  return {{640, 480}, {0.0, kSweepAngleDeg, -25.0}, {0, 1, 2, 4, 8}, windows, true};
}

// Centre-cropped to the target's aspect ratio, then resampled to its size (area averaging when
// shrinking).
cv::Mat fitTo(const cv::Mat& image, cv::Size size) {
  const double target = double(size.width) / size.height;
  cv::Rect crop(0, 0, image.cols, image.rows);
  if (double(image.cols) / image.rows > target) {
    crop.width = int(std::lround(image.rows * target));
    crop.x = (image.cols - crop.width) / 2;
  } else {
    crop.height = int(std::lround(image.cols / target));
    crop.y = (image.rows - crop.height) / 2;
  }
  cv::Mat out;
  const bool shrinking = crop.width >= size.width;
  cv::resize(image(crop), out, size, 0, 0, shrinking ? cv::INTER_AREA : cv::INTER_LINEAR);
  return out;
}

// Frame `index` (position in the clip, not number) of a clip, in the file's own encoding (the
// values the solver works on, frame_stack.h), clamped to 0..1.
cv::Mat readFrame(ClipReader& reader, size_t index) {
  Image image = reader.read(reader.info().frames.at(index));
  cv::Mat rgb = rgbMat(image);
  cv::patchNaNs(rgb, 0.0);
  return cv::min(cv::max(rgb, 0.0), 1.0);  // the 0..1 of derain_solver.h
}

struct Background {
  std::string scene;
  cv::Mat pixels;
};

std::vector<Background> loadBackgrounds(const DerainReportSettings& settings, cv::Size size,
                                        std::vector<std::string>& notes) {
  std::vector<Background> out;
  {
    auto reader = openClip(settings.examplePlate);
    out.push_back({"street", fitTo(readFrame(*reader, 0), size)});
  }
  if (settings.quick) return out;
  const fs::path data = settings.sharedData;
  // Not plate_static/opencv_vtest.avi: the example plate is cut from it (README), so it would
  // repeat the street case. A sunny street with sky and cobbles, and a weir with water instead.
  const std::pair<const char*, const char*> extra[] = {{"lund", "sfm/opensfm_lund/01.jpg"},
                                                       {"weir", "stitching/weir/weir_1.jpg"}};
  for (const auto& [scene, file] : extra) {
    if (data.empty() || !fs::exists(data / file)) {
      notes.push_back(fmt::format("background '{}' left out: {} not found", scene,
                                  data.empty() ? std::string(file) : (data / file).string()));
      continue;
    }
    auto reader = openClip((data / file).string());
    out.push_back({scene, fitTo(readFrame(*reader, 0), size)});
  }
  return out;
}

// The median baseline's matte (derain_report.h): the positive luminance residual over the
// headroom to white. 0 where `valid` (when given) is 0.
cv::Mat impliedMatte(const cv::Mat& frame, const cv::Mat& background, const cv::Mat& valid) {
  cv::Mat alpha(frame.size(), CV_32FC1);
  for (int y = 0; y < frame.rows; ++y) {
    const cv::Vec3f* i = frame.ptr<cv::Vec3f>(y);
    const cv::Vec3f* s = background.ptr<cv::Vec3f>(y);
    const uint8_t* v = valid.empty() ? nullptr : valid.ptr<uint8_t>(y);
    float* a = alpha.ptr<float>(y);
    for (int x = 0; x < frame.cols; ++x) {
      const double headroom = std::max(1e-3, 1.0 - rec709Luminance(s[x]));
      const double value = (rec709Luminance(i[x]) - rec709Luminance(s[x])) / headroom;
      a[x] = (v && !v[x]) ? 0.0f : float(std::clamp(value, 0.0, 1.0));
    }
  }
  return alpha;
}

std::vector<cv::Mat> impliedMattes(const FrameStack& stack, const cv::Mat& background) {
  std::vector<cv::Mat> out;
  for (size_t k = 0; k < stack.frames.size(); ++k)
    out.push_back(impliedMatte(stack.frames[k], background,
                               stack.valid.empty() ? cv::Mat() : stack.valid[k]));
  return out;
}

double meanAbsDifference(const std::vector<cv::Mat>& a, const std::vector<cv::Mat>& b) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    sum += cv::norm(a[k], b[k], cv::NORM_L1);
    count += a[k].total();
  }
  return sum / double(count);
}

double meanValue(const std::vector<cv::Mat>& mattes) {
  double sum = 0.0;
  size_t count = 0;
  for (const cv::Mat& m : mattes) {
    sum += cv::sum(m)[0];
    count += m.total();
  }
  return count ? sum / double(count) : 0.0;
}

FrameStack firstFrames(const FrameStack& stack, int n) {
  FrameStack out;
  out.frames.assign(stack.frames.begin(), stack.frames.begin() + n);
  return out;
}

// One case's truth and the frames a method sees.
struct Case {
  std::string scene;
  const SyntheticRain* rain;
  int frames;  // the first `frames` of the synthetic stack
};

DerainReportRow rowFor(const std::string& section, const Case& c, const std::string& method) {
  DerainReportRow row;
  row.section = section;
  row.scene = c.scene;
  row.trueAngleDeg = c.rain->angleDeg;
  row.method = method;
  row.frames = c.frames;
  row.objective = row.dataRms = kNaN;
  return row;
}

void measureBackground(DerainReportRow& row, const cv::Mat& estimate, const cv::Mat& truth) {
  const cv::Mat clamped = cv::min(cv::max(estimate, 0.0), 1.0);
  row.psnrDb = psnrDb(clamped, truth);
  row.ssim = ssim(clamped, truth);
}

std::vector<cv::Mat> trueMattes(const Case& c) {
  return {c.rain->alpha.begin(), c.rain->alpha.begin() + c.frames};
}

// No derain at all: frame 0 as the background, no rain anywhere.
DerainReportRow runInput(const std::string& section, const Case& c) {
  DerainReportRow row = rowFor(section, c, "input");
  measureBackground(row, c.rain->stack.frames[0], c.rain->background);
  row.alphaMae = meanValue(trueMattes(c));
  row.angleDeg = row.angleErrorDeg = row.seconds = kNaN;
  return row;
}

struct MedianOutput {
  cv::Mat background;
  std::vector<cv::Mat> alpha;
};

DerainReportRow runMedian(const std::string& section, const Case& c, MedianOutput* keep) {
  DerainReportRow row = rowFor(section, c, "median");
  const FrameStack stack = firstFrames(c.rain->stack, c.frames);
  const auto start = Clock::now();
  const cv::Mat background = temporalMedian(stack);
  std::vector<cv::Mat> alpha = impliedMattes(stack, background);
  row.angleDeg = estimateRainAngle(alpha).angleDeg;
  row.seconds = secondsSince(start);
  measureBackground(row, background, c.rain->background);
  row.alphaMae = meanAbsDifference(alpha, trueMattes(c));
  row.angleErrorDeg = std::abs(foldRainAngleDeg(row.angleDeg - row.trueAngleDeg));
  if (keep) *keep = {background, std::move(alpha)};
  return row;
}

// The solve on the frames as they are ("solver", what --no-register does), or, `registered`, as
// `pluvia derain` runs it by default: registration decided from evidence first (a locked-off
// camera is left alone; derain/registration.h), timed with the solve ("default").
DerainReportRow runSolver(const std::string& section, const Case& c, const DerainSettings& settings,
                          DerainResult* keep, bool registered = false) {
  DerainReportRow row = rowFor(section, c, registered ? "default" : "solver");
  const FrameStack stack = firstFrames(c.rain->stack, c.frames);
  const auto start = Clock::now();
  DerainResult result;
  if (registered) {
    const Registration registration = registerFrames(stack.frames, int(stack.frames.size() / 2));
    DerainSettings s = settings;
    if (registration.moving()) s.registrationErrorPx = kResidualMisregistrationPx;
    result = solveDerain(warpToReference(stack.frames, registration), s);
  } else {
    result = solveDerain(stack, settings);
  }
  row.seconds = secondsSince(start);
  row.iterations = result.iterations;
  measureBackground(row, result.background, c.rain->background);
  row.alphaMae = meanAbsDifference(result.alpha, trueMattes(c));
  row.angleDeg = result.angleDeg;
  row.angleErrorDeg = std::abs(foldRainAngleDeg(row.angleDeg - row.trueAngleDeg));
  if (!result.history.empty()) {
    row.objective = result.history.back().objective;
    row.dataRms = result.history.back().dataRms;
  }
  if (keep) *keep = std::move(result);
  return row;
}

void writePreview(const fs::path& path, const cv::Mat& rgb) {
  cv::Mat bgr, bytes;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  bgr.convertTo(bytes, CV_8UC3, 255.0);
  if (!cv::imwrite(path.string(), bytes))
    throw Error("cannot write an image", {"report", {}, path});
}

void writeMattePreview(const fs::path& path, const cv::Mat& alpha) {
  cv::Mat bytes;
  alpha.convertTo(bytes, CV_8UC1, 255.0 * kMatteViewGain);  // saturates at 255
  if (!cv::imwrite(path.string(), bytes))
    throw Error("cannot write an image", {"report", {}, path});
}

// The flow-registered temporal median of clean_plate.h for frame `reference`, in the solver's
// values (RGB 0..1).
cv::Mat flowRegisteredMedian(const std::vector<cv::Mat>& frames, int reference) {
  std::vector<cv::Mat3f> codes;
  for (const cv::Mat& frame : frames) codes.push_back(cv::Mat3f(frame * 255.0));
  return cleanPlatesRgb(codes, {reference}).front().plate / 255.0;
}

// (a') A camera moving past two depths (parallax_clip.h) with rain, its answer the middle
// frame's clean image: the rained frame, the flow-registered median (clean_plate.h), the solve
// after a homography alone, and the default (homography, then dense flow where it leaves
// parallax).
void runMoving(const Background& background, const DerainReportSettings& settings,
               DerainReport& report) {
  const std::vector<cv::Mat> clean = makeParallaxClip(background.pixels, background.pixels.size());
  SyntheticRainSettings rainSettings;
  rainSettings.frames = int(clean.size());
  rainSettings.angleDeg = kSweepAngleDeg;
  rainSettings.seed = settings.seed;
  const SyntheticRain rain = makeSyntheticRainOver(clean, rainSettings);
  const int reference = int(clean.size() / 2);
  const cv::Mat& answer = clean[size_t(reference)];
  const Case moving{background.scene, &rain, rainSettings.frames};
  const auto row = [&](const std::string& method, const cv::Mat& estimate, double seconds) {
    DerainReportRow r = rowFor("moving", moving, method);
    measureBackground(r, estimate, answer);
    r.alphaMae = r.angleDeg = r.angleErrorDeg = kNaN;
    r.seconds = seconds;
    return r;
  };
  report.rows.push_back(row("input", rain.stack.frames[size_t(reference)], kNaN));
  auto start = Clock::now();
  const cv::Mat median = flowRegisteredMedian(rain.stack.frames, reference);
  report.rows.push_back(row("median", median, secondsSince(start)));
  for (const bool dense : {false, true}) {
    start = Clock::now();
    const Registration registration = registerFrames(rain.stack.frames, reference, dense);
    DerainSettings solver = settings.solver;
    if (registration.moving()) solver.registrationErrorPx = kResidualMisregistrationPx;
    const DerainResult result =
        solveDerain(warpToReference(rain.stack.frames, registration), solver);
    DerainReportRow r =
        row(dense ? "default" : "homography", result.background, secondsSince(start));
    r.iterations = result.iterations;
    r.angleDeg = result.angleDeg;
    r.angleErrorDeg = std::abs(foldRainAngleDeg(r.angleDeg - r.trueAngleDeg));
    report.rows.push_back(r);
    if (dense && !settings.imagesDir.empty()) {
      const fs::path out = settings.imagesDir;
      writePreview(out / "moving_truth.png", answer);
      writePreview(out / "moving_input.png", rain.stack.frames[size_t(reference)]);
      writePreview(out / "moving_median.png", median);
      writePreview(out / "moving_default.png", result.background);
    }
  }
}

void runRealFootage(const DerainReportSettings& settings, DerainReport& report) {
  const fs::path dir = fs::path(settings.sharedData) / kRealFootage;
  if (settings.sharedData.empty() || !fs::exists(dir / "00001.jpg")) {
    report.notes.push_back(fmt::format(
        "real footage left out: {} not found",
        settings.sharedData.empty() ? std::string(kRealFootage) : (dir / "00001.jpg").string()));
    return;
  }
  DerainRealFootage& real = report.real;
  real.path = (dir / "%05d.jpg").string();
  auto reader = openClip(real.path);
  const size_t n = std::min<size_t>(size_t(settings.frames), reader->info().frames.size());
  if (n < 3) {
    report.notes.push_back("real footage left out: fewer than 3 frames");
    return;
  }
  std::vector<cv::Mat> frames;
  for (size_t k = 0; k < n; ++k) {
    cv::Mat frame = readFrame(*reader, k);
    // Only ever shrunk, to the synthetic cases' width, keeping the aspect ratio.
    if (frame.cols > 640)
      cv::resize(frame, frame, {}, 640.0 / frame.cols, 640.0 / frame.cols, cv::INTER_AREA);
    frames.push_back(frame);
  }
  real.present = true;
  real.frames = int(n);
  real.size = frames[0].size();
  real.reference = int(n / 2);
  log::info(fmt::format("report derain: real footage, registering {} frames", n));
  auto start = Clock::now();
  const Registration registration = registerFrames(frames, real.reference);
  const FrameStack stack = warpToReference(frames, registration);
  real.registrationSeconds = secondsSince(start);
  real.maxShiftPx = registration.maxShiftPx;
  const cv::Mat median = temporalMedian(stack);
  real.medianAngleDeg = estimateRainAngle(impliedMattes(stack, median)).angleDeg;
  log::info("report derain: real footage, solving");
  start = Clock::now();
  DerainSettings solver = settings.solver;
  if (registration.moving()) solver.registrationErrorPx = kResidualMisregistrationPx;
  real.result = solveDerain(stack, solver);
  real.solveSeconds = secondsSince(start);
  real.meanAlpha = meanValue(real.result.alpha);
  if (!settings.imagesDir.empty()) {
    const fs::path out = settings.imagesDir;
    writePreview(out / "real_input.png", stack.frames[size_t(real.reference)]);
    writePreview(out / "real_median.png", median);
    writePreview(out / "real_clean_plate.png", real.result.background);
    writeMattePreview(out / "real_matte_x4.png", real.result.alpha[size_t(real.reference)]);
  }
}

std::string general(double value) {
  return std::isfinite(value) ? fmt::format("{:.4g}", value) : "-";
}

}  // namespace

DerainReport runDerainReport(const DerainReportSettings& settings) {
  if (settings.frames < 3) throw UsageError("report derain: at least 3 frames per case");
  const Plan plan = planFor(settings);
  DerainReport report;
  report.size = plan.size;
  report.frames = settings.frames;
  report.noiseSigma = SyntheticRainSettings{}.noiseSigma;
  if (!settings.imagesDir.empty()) fs::create_directories(settings.imagesDir);

  const std::vector<Background> backgrounds = loadBackgrounds(settings, plan.size, report.notes);
  for (const Background& background : backgrounds) {
    for (double angle : plan.angles) {
      SyntheticRainSettings rainSettings;
      rainSettings.frames = settings.frames;
      rainSettings.angleDeg = angle;
      rainSettings.seed = settings.seed;
      const SyntheticRain rain = makeSyntheticRain(background.pixels, rainSettings);
      const Case full{background.scene, &rain, settings.frames};
      log::info(fmt::format("report derain: {} at {} degrees", background.scene, angle));
      // The sweeps and the previews use the first background at the sweep angle.
      const bool sweepCase = &background == &backgrounds.front() && angle == kSweepAngleDeg;
      MedianOutput median;
      DerainResult solved;
      report.rows.push_back(runInput("synthetic", full));
      report.rows.push_back(runMedian("synthetic", full, sweepCase ? &median : nullptr));
      report.rows.push_back(
          runSolver("synthetic", full, settings.solver, sweepCase ? &solved : nullptr));
      report.rows.push_back(runSolver("synthetic", full, settings.solver, nullptr, true));
      if (!sweepCase) continue;
      if (!settings.imagesDir.empty()) {
        const fs::path out = settings.imagesDir;
        writePreview(out / "synthetic_truth.png", rain.background);
        writePreview(out / "synthetic_input.png", rain.stack.frames[0]);
        writePreview(out / "synthetic_median.png", median.background);
        writePreview(out / "synthetic_solver.png", solved.background);
        writeMattePreview(out / "synthetic_matte_true_x4.png", rain.alpha[0]);
        writeMattePreview(out / "synthetic_matte_median_x4.png", median.alpha[0]);
        writeMattePreview(out / "synthetic_matte_solver_x4.png", solved.alpha[0]);
      }
      for (int iterations : plan.iterations) {
        log::info(fmt::format("report derain: sweep, {} iterations", iterations));
        DerainSettings s = settings.solver;
        s.maxIterations = iterations;
        s.tolerance = 0.0;
        report.rows.push_back(runSolver("iterations", full, s, nullptr));
      }
      for (int window : plan.windows) {
        log::info(fmt::format("report derain: sweep, window of {} frames", window));
        const Case part{background.scene, &rain, window};
        report.rows.push_back(runMedian("window", part, nullptr));
        report.rows.push_back(runSolver("window", part, settings.solver, nullptr));
      }
    }
  }
  log::info("report derain: a moving camera with parallax");
  runMoving(backgrounds.front(), settings, report);
  if (plan.real && !runRealPart("report derain", "real footage", report.notes,
                                [&] { runRealFootage(settings, report); }))
    report.real.present = false;
  if (!settings.imagesDir.empty())
    report.notes.push_back("previews written to " + settings.imagesDir);
  return report;
}

std::string formatDerainReport(const DerainReport& report) {
  std::string out = fmt::format(
      "Rain extraction (Wang et al. Eq. 1) against synthetic ground truth: {} frames of {}x{} "
      "per case, sensor noise sigma {} in display encoding.\n"
      "PSNR and SSIM of S against the true background, both in display encoding (the values "
      "the solver works on, clamped to [0, 1]). alpha MAE: mean |alpha - truth| over "
      "all pixels and frames; the median's matte is clamp(Y(I - S) / (1 - Y(S)), 0, 1) (rain "
      "taken as white), its angle estimateRainAngle of those mattes. 'input': frame 0 as S, no "
      "rain found. Times: wall clock, whole stack. objective: DerainIteration::objective (Eq. 1 "
      "per "
      "pixel per frame, in the solver's units).\n\n",
      report.frames, report.size.width, report.size.height, report.noiseSigma);
  // The columns, for the header and each row.
  static constexpr char kColumns[] =
      "{:<10} {:<6} {:>6} {:<7} {:>6} {:>5} {:>7} {:>7} {:>9} {:>7} {:>6} {:>8} {:>8} "
      "{:>10} {:>8}\n";
  out += fmt::format(kColumns, "section", "scene", "true°", "method", "frames", "iters", "PSNR dB",
                     "SSIM", "alpha MAE", "angle°", "err°", "seconds", "s/frame", "objective",
                     "data RMS");
  for (const DerainReportRow& row : report.rows) {
    out += fmt::format(
        kColumns, row.section, row.scene, fixedOrDash(row.trueAngleDeg, 1), row.method, row.frames,
        row.method != "median" && row.method != "input" ? std::to_string(row.iterations) : "-",
        fixedOrDash(row.psnrDb, 2), fixedOrDash(row.ssim, 4), fixedOrDash(row.alphaMae, 4),
        fixedOrDash(row.angleDeg, 2), fixedOrDash(row.angleErrorDeg, 2),
        fixedOrDash(row.seconds, 2), fixedOrDash(row.seconds / row.frames, 3),
        general(row.objective), fixedOrDash(row.dataRms, 5));
  }

  // The targets, over the synthetic cases: each solver row against the median row of its case.
  double worstGain = 1e300, sumGain = 0.0;
  double worstAngle = 0.0, worstPerFrame = 0.0;
  int cases = 0;
  for (size_t i = 0; i + 1 < report.rows.size(); ++i) {
    const DerainReportRow& m = report.rows[i];
    const DerainReportRow& s = report.rows[i + 1];
    if (m.section != "synthetic" || m.method != "median" || s.method != "solver") continue;
    ++cases;
    worstGain = std::min(worstGain, s.psnrDb - m.psnrDb);
    sumGain += s.psnrDb - m.psnrDb;
    worstAngle = std::max(worstAngle, s.angleErrorDeg);
    worstPerFrame = std::max(worstPerFrame, s.seconds / s.frames);
  }
  // The locked-off cases: the default path (registration decided from evidence) against the
  // solve on the frames as they are.
  double worstDefault = 1e300;
  int defaults = 0;
  for (size_t i = 0; i + 1 < report.rows.size(); ++i) {
    const DerainReportRow& s = report.rows[i];
    const DerainReportRow& d = report.rows[i + 1];
    if (s.section != "synthetic" || s.method != "solver" || d.method != "default") continue;
    ++defaults;
    worstDefault = std::min(worstDefault, d.psnrDb - s.psnrDb);
  }
  if (cases > 0) {
    auto verdict = [](bool met) { return met ? "met" : "NOT met"; };
    if (defaults > 0)
      out += fmt::format(
          "\nLocked-off camera, over {} synthetic cases: the default path (registration decided "
          "from evidence) against the solve with --no-register: {:+.2f} dB worst (target within "
          "1 dB: {}).",
          defaults, worstDefault, verdict(worstDefault >= -1.0));
    out += fmt::format(
        "\nOver {} synthetic cases, solver against median: PSNR {:+.2f} dB worst, {:+.2f} dB "
        "mean (target >= +1 dB: {}); worst angle error {:.2f}° (target <= 2°: {}); worst {:.3f} s "
        "per "
        "{}x{} frame (target <= 2 s: {}).\n",
        cases, worstGain, sumGain / cases, verdict(worstGain >= 1.0), worstAngle,
        verdict(worstAngle <= 2.0), worstPerFrame, report.size.width, report.size.height,
        verdict(worstPerFrame <= 2.0));
  }

  // The moving camera: the default against the flow-registered median and the homography alone.
  const auto movingRow = [&](const std::string& method) -> const DerainReportRow* {
    for (const DerainReportRow& row : report.rows)
      if (row.section == "moving" && row.method == method) return &row;
    return nullptr;
  };
  const DerainReportRow *median = movingRow("median"), *homography = movingRow("homography"),
                        *dense = movingRow("default");
  if (median && homography && dense)
    out += fmt::format(
        "\nMoving camera with parallax ({} frames of pillars crossing a street 3.5 times as fast "
        "as it): the default path {:+.2f} dB against the flow-registered median (target within "
        "3 dB: {}), {:+.2f} dB against the homography alone.\n",
        dense->frames, dense->psnrDb - median->psnrDb,
        dense->psnrDb >= median->psnrDb - 3.0 ? "met" : "NOT met",
        dense->psnrDb - homography->psnrDb);

  const DerainRealFootage& real = report.real;
  if (real.present) {
    out += fmt::format(
        "\nReal footage {}: {} frames {}x{}, registered onto frame {} of the window (largest "
        "corner shift {:.1f} px, {:.2f} s), then solved in {:.2f} s ({:.3f} s per frame).\n",
        real.path, real.frames, real.size.width, real.size.height, real.reference + 1,
        real.maxShiftPx, real.registrationSeconds, real.solveSeconds,
        real.solveSeconds / real.frames);
    out += fmt::format("{:>9} {:>12} {:>10} {:>8} {:>9} {:>9} {:>8}\n", "iteration", "objective",
                       "data RMS", "angle°", "seconds", "CG alpha", "CG S");
    for (const DerainIteration& it : real.result.history) {
      out += fmt::format("{:>9} {:>12.7f} {:>10.6f} {:>8.2f} {:>9.2f} {:>9} {:>8}\n", it.iteration,
                         it.objective, it.dataRms, it.angleDeg, it.seconds, it.cgIterationsAlpha,
                         it.cgIterationsS);
    }
    const cv::Vec3f c = real.result.rainColor.empty() ? cv::Vec3f() : real.result.rainColor[0];
    out += fmt::format(
        "solver: rain angle {:.2f}° after {} iterations (median baseline's mattes: {:.2f}°), rain "
        "colour of frame 1 ({:.3f}, {:.3f}, {:.3f}), mean alpha {:.4f}, noise sigma {:.4f}.\n",
        real.result.angleDeg, real.result.iterations, real.medianAngleDeg, c[0], c[1], c[2],
        real.meanAlpha, real.result.noiseSigma);
  }
  for (const std::string& note : report.notes) out += "note: " + note + "\n";
  return out;
}

void writeDerainReportCsv(const DerainReport& report, const std::string& path) {
  writeReportCsv(
      path,
      "section,scene,true_angle_deg,method,frames,iterations,psnr_db,ssim,"
      "alpha_mae,angle_deg,angle_error_deg,seconds,seconds_per_frame,objective,data_rms",
      [&](std::ostream& file) {
        for (const DerainReportRow& row : report.rows) {
          file << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", row.section,
                              row.scene, csvNumber(row.trueAngleDeg), row.method, row.frames,
                              row.method == "solver" ? std::to_string(row.iterations) : "",
                              csvNumber(row.psnrDb), csvNumber(row.ssim), csvNumber(row.alphaMae),
                              csvNumber(row.angleDeg), csvNumber(row.angleErrorDeg),
                              csvNumber(row.seconds), csvNumber(row.seconds / row.frames),
                              csvNumber(row.objective), csvNumber(row.dataRms));
        }
        if (report.real.present) {
          for (const DerainIteration& it : report.real.result.history) {
            file << fmt::format("real,nturain_ra1,,solver,{},{},,,,,{},,{},{},{},{}\n",
                                report.real.frames, it.iteration, csvNumber(it.angleDeg),
                                csvNumber(it.seconds), csvNumber(it.seconds / report.real.frames),
                                csvNumber(it.objective), csvNumber(it.dataRms));
          }
        }
      });
}

}  // namespace pluvia::lab
