#include "derain/derain_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "derain/rain_direction.h"
#include "derain/sparse_solve.h"
#include "util/error.h"
#include "util/median.h"
#include "util/parallel.h"

namespace pluvia::derain {
namespace {

// Added to every diagonal so each sub-problem stays positive definite where the data says
// nothing (alpha where C == S, S where no frame saw the pixel). Small against any real weight.
constexpr float kRidge = 1e-6f;
// A new D0 is taken only when its line stands out of the spectrum this clearly and this share
// of the tiles agree on it (rain_direction.h); below, the mattes hold no directional structure
// (no rain) and D0 keeps its value.
constexpr double kMinDirectionSalience = 1.12;
constexpr double kMinDirectionAgreement = 0.3;
// The rain colour of a frame is refitted only when its mattes carry at least this much
// sum of alpha^2 per pixel; below, C keeps its value (no rain to measure it on).
constexpr double kMinAlphaEnergyPerPixel = 1e-5;
// After its solve alpha is projected onto [0, 1], and set to 0 where the rain it claims,
// |alpha (C - S)|, is within this many noise sigmas: clipping noise at 0 alone would keep its
// positive half as rain and bias S low by about 0.4 sigma everywhere.
constexpr double kNoiseDeadzone = 3.0;

// The solver works in 8-bit code values (0..255), the units of the paper's video in which its
// lambda and mu were chosen (mu is relative to intensity squared, so the scale matters).
constexpr float kCodeValueScale = 255.0f;

// One frame's data as planar float arrays, R, G, B planes, plus its validity.
struct PlanarFrame {
  std::vector<float> rgb[3];
  std::vector<float> valid;  // 1 or 0
};

struct Problem {
  GridSize grid;
  std::vector<PlanarFrame> frames;
};

Problem makeProblem(const FrameStack& stack) {
  if (stack.frames.size() < 3) {
    throw Error(fmt::format("rain extraction needs at least 3 frames, got {}", stack.frames.size()),
                {"derain"});
  }
  const cv::Size size = stack.size();
  if (size.width < 2 || size.height < 2)
    throw Error("rain extraction needs frames of at least 2 x 2 pixels", {"derain"});
  if (!stack.valid.empty() && stack.valid.size() != stack.frames.size())
    throw Error("rain extraction: one validity mask per frame is needed", {"derain"});
  Problem problem;
  problem.grid = {size.width, size.height};
  const size_t n = problem.grid.count();
  for (size_t k = 0; k < stack.frames.size(); ++k) {
    const cv::Mat& frame = stack.frames[k];
    if (frame.size() != size || frame.type() != CV_32FC3) {
      throw Error(
          fmt::format("rain extraction: frame {} is {}x{} (type {}), frame 0 is {}x{} RGB float", k,
                      frame.cols, frame.rows, frame.type(), size.width, size.height),
          {"derain"});
    }
    PlanarFrame planar;
    for (auto& plane : planar.rgb) plane.resize(n);
    planar.valid.assign(n, 1.0f);
    for (int y = 0; y < size.height; ++y) {
      const cv::Vec3f* row = frame.ptr<cv::Vec3f>(y);
      const uint8_t* mask = stack.valid.empty() ? nullptr : stack.valid[k].ptr<uint8_t>(y);
      for (int x = 0; x < size.width; ++x) {
        const size_t p = size_t(y) * size.width + x;
        const cv::Vec3f v = row[x];
        const bool finite = std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
        const bool ok = finite && (!mask || mask[x]);
        for (int c = 0; c < 3; ++c) planar.rgb[c][p] = ok ? kCodeValueScale * v[c] : 0.0f;
        planar.valid[p] = ok ? 1.0f : 0.0f;
      }
    }
    problem.frames.push_back(std::move(planar));
  }
  return problem;
}

struct State {
  std::vector<float> background[3];       // S per channel
  std::vector<std::vector<float>> alpha;  // per frame
  std::vector<cv::Vec3f> color;           // C per frame
  double angleDeg = 0.0;
};

std::vector<float> medianPlane(const Problem& problem, int channel) {
  const size_t n = problem.grid.count();
  std::vector<float> median(n, 0.0f);
  forEachBlock(n, 4096, [&](size_t begin, size_t end) {
    std::vector<float> values;
    for (size_t p = begin; p < end; ++p) {
      values.clear();
      for (const auto& frame : problem.frames)
        if (frame.valid[p] > 0) values.push_back(frame.rgb[channel][p]);
      if (!values.empty()) median[p] = medianInPlace(values.data(), values.size());
    }
  });
  return median;
}

// Sensor noise from the residual against the median: 1.4826 * MAD, over a sparse sample of
// valid pixels. Rain touches few of them, so it barely moves the estimate.
double estimateNoiseSigma(const Problem& problem, const State& state) {
  std::vector<float> residuals;
  const size_t n = problem.grid.count();
  const size_t stride = std::max<size_t>(1, n * problem.frames.size() * 3 / 400000);
  size_t counter = 0;
  for (const auto& frame : problem.frames)
    for (int c = 0; c < 3; ++c)
      for (size_t p = 0; p < n; ++p)
        if (frame.valid[p] > 0 && counter++ % stride == 0)
          residuals.push_back(frame.rgb[c][p] - state.background[c][p]);
  if (residuals.empty()) return 0.0;
  const float centre = median(residuals);
  for (float& r : residuals) r = std::abs(r - centre);
  return 1.4826 * double(median(residuals));
}

// The initial rain colour of a frame: the bright end (99.5th percentile) of its valid pixels
// per channel. The C step refits it from the first mattes.
cv::Vec3f initialRainColor(const Problem& problem, const PlanarFrame& frame) {
  cv::Vec3f color;
  for (int c = 0; c < 3; ++c) {
    std::vector<float> values;
    for (size_t p = 0; p < problem.grid.count(); ++p)
      if (frame.valid[p] > 0) values.push_back(frame.rgb[c][p]);
    if (values.empty()) continue;
    const size_t at = std::min(values.size() - 1, size_t(0.995 * double(values.size())));
    std::nth_element(values.begin(), values.begin() + at, values.end());
    color[c] = std::max(0.0f, values[at]);
  }
  return color;
}

// Per pixel, the rain contrast below which alpha is taken as noise: kNoiseDeadzone times the
// noise, where the noise is the sensor's plus, for registered frames, the error a residual
// misregistration of `registrationErrorPx` makes on the background's gradient (edges would
// otherwise come out as rain).
std::vector<float> alphaDeadzone(const Problem& problem, const State& state, double noiseSigma,
                                 double registrationErrorPx) {
  const GridSize& g = problem.grid;
  std::vector<float> deadzone(g.count());
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const size_t p = size_t(y) * g.width + x;
      double gradient = 0.0;
      for (int c = 0; c < 3; ++c) {
        const std::vector<float>& s = state.background[c];
        const double gx = 0.5 * (s[p + (x + 1 < g.width)] - s[p - (x > 0)]);
        const double gy =
            0.5 * (s[p + (y + 1 < g.height) * size_t(g.width)] - s[p - (y > 0) * size_t(g.width)]);
        gradient = std::max(gradient, std::hypot(gx, gy));
      }
      const double misregistration = registrationErrorPx * gradient;
      deadzone[p] = float(kNoiseDeadzone *
                          std::sqrt(noiseSigma * noiseSigma + misregistration * misregistration));
    }
  return deadzone;
}

// Alpha step for frame k: (diag(v |C - S|^2) + mu G^T G) alpha = v (C - S) . (I - S),
// then projected onto [0, 1].
int solveAlpha(const Problem& problem, const State& state, size_t k, const DerainSettings& settings,
               const std::vector<float>& deadzone, std::vector<float>& alpha) {
  const GridSize& grid = problem.grid;
  const size_t n = grid.count();
  const PlanarFrame& frame = problem.frames[k];
  const cv::Vec3f color = state.color[k];
  std::vector<float> diagonal(n), b(n), data(n);
  for (size_t p = 0; p < n; ++p) {
    float a = 0.0f, rhs = 0.0f;
    for (int c = 0; c < 3; ++c) {
      const float d = color[c] - state.background[c][p];
      a += d * d;
      rhs += d * (frame.rgb[c][p] - state.background[c][p]);
    }
    data[p] = frame.valid[p] * a + kRidge;
    b[p] = frame.valid[p] * rhs;
  }
  diagonal = data;
  const cv::Vec2d d0 = streakDirection(state.angleDeg);
  addDirectionalGramDiagonal(grid, d0[0], d0[1], settings.mu, diagonal.data());
  auto apply = [&](const float* x, float* y) {
    for (size_t p = 0; p < n; ++p) y[p] = data[p] * x[p];
    addDirectionalGram(grid, d0[0], d0[1], settings.mu, x, y);
  };
  const CgResult cg = solveConjugateGradient(apply, diagonal, b, alpha, settings.cgMaxIterations,
                                             settings.cgTolerance);
  for (size_t p = 0; p < n; ++p) {
    const float a = alpha[p];
    const float contrast = a * std::sqrt(data[p]);  // |alpha (C - S)|, what the frame shows
    alpha[p] = std::isfinite(a) && contrast > deadzone[p] ? std::min(a, 1.0f) : 0.0f;
  }
  return cg.iterations;
}

// Rain is transient: what alpha holds at a pixel in every frame of the window is a residual of
// the background (its smoothing by lambda, a misregistered edge), not rain. Left in, it would
// take away all of S's data at that pixel, and S would drift with nothing to hold it.
void removePersistentAlpha(const Problem& problem, State& state) {
  const size_t n = problem.grid.count();
  forEachBlock(n, 4096, [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p) {
      float persistent = 1.0f;
      for (size_t k = 0; k < problem.frames.size(); ++k)
        if (problem.frames[k].valid[p] > 0) persistent = std::min(persistent, state.alpha[k][p]);
      if (persistent <= 0.0f) continue;
      for (auto& alpha : state.alpha) alpha[p] = std::max(0.0f, alpha[p] - persistent);
    }
  });
}

// The initialisation's rain: each frame's excess over the background S (the temporal median),
// averaged over the channels, where valid. Its streaks give D0 before the first alpha solve,
// which smooths alpha along D0.
std::vector<cv::Mat> residualMattes(const Problem& problem, const State& state) {
  std::vector<cv::Mat> mattes;
  for (const PlanarFrame& frame : problem.frames) {
    cv::Mat matte(problem.grid.height, problem.grid.width, CV_32F);
    float* m = matte.ptr<float>();
    for (size_t p = 0; p < problem.grid.count(); ++p) {
      float excess = 0.0f;
      for (int c = 0; c < 3; ++c) excess += frame.rgb[c][p] - state.background[c][p];
      m[p] = frame.valid[p] > 0 ? std::max(0.0f, excess / 3.0f) : 0.0f;
    }
    mattes.push_back(matte);
  }
  return mattes;
}

// The mattes with what stays in place through the window taken out (alpha minus its temporal
// median): rain moves between frames, while what a misregistered edge or a compression
// artefact leaves in alpha stays put and would otherwise pull D0 along the scene's lines.
std::vector<cv::Mat> transientMattes(const Problem& problem, const State& state) {
  const size_t n = problem.grid.count();
  std::vector<cv::Mat> mattes;
  for (size_t k = 0; k < problem.frames.size(); ++k)
    mattes.push_back(cv::Mat(problem.grid.height, problem.grid.width, CV_32F));
  forEachBlock(n, 4096, [&](size_t begin, size_t end) {
    std::vector<float> values;
    for (size_t p = begin; p < end; ++p) {
      values.clear();
      for (size_t k = 0; k < problem.frames.size(); ++k)
        if (problem.frames[k].valid[p] > 0) values.push_back(state.alpha[k][p]);
      const float persistent = values.empty() ? 0.0f : median(values);
      for (size_t k = 0; k < problem.frames.size(); ++k)
        mattes[k].ptr<float>()[p] = std::max(0.0f, state.alpha[k][p] - persistent);
    }
  });
  return mattes;
}

// C step: per frame and channel, C = sum v alpha (I - (1 - alpha) S) / sum v alpha^2.
void solveColor(const Problem& problem, State& state) {
  const size_t n = problem.grid.count();
  for (size_t k = 0; k < problem.frames.size(); ++k) {
    const PlanarFrame& frame = problem.frames[k];
    const std::vector<float>& alpha = state.alpha[k];
    double energy = 0.0;
    double numerator[3] = {0, 0, 0};
    for (size_t p = 0; p < n; ++p) {
      const double a = frame.valid[p] * alpha[p];
      energy += a * alpha[p];
      for (int c = 0; c < 3; ++c)
        numerator[c] += a * (frame.rgb[c][p] - (1.0 - alpha[p]) * state.background[c][p]);
    }
    if (energy < kMinAlphaEnergyPerPixel * double(n)) continue;
    for (int c = 0; c < 3; ++c) state.color[k][c] = float(std::max(0.0, numerator[c] / energy));
  }
}

// S step, per channel: (diag(sum_k v (1 - alpha)^2) + lambda L) S = sum_k v (1 - alpha)(I - alpha
// C).
int solveBackground(const Problem& problem, State& state, const DerainSettings& settings) {
  const GridSize& grid = problem.grid;
  const size_t n = grid.count();
  std::vector<float> data(n, kRidge);
  for (size_t k = 0; k < problem.frames.size(); ++k)
    for (size_t p = 0; p < n; ++p) {
      const float keep = 1.0f - state.alpha[k][p];
      data[p] += problem.frames[k].valid[p] * keep * keep;
    }
  std::vector<float> diagonal = data;
  addLaplacianDiagonal(grid, settings.lambda, diagonal.data());
  int iterations[3] = {0, 0, 0};
  forEachIndex(3, [&](int c) {
    std::vector<float> b(n, 0.0f);
    for (size_t k = 0; k < problem.frames.size(); ++k) {
      const PlanarFrame& frame = problem.frames[k];
      const float color = state.color[k][c];
      for (size_t p = 0; p < n; ++p) {
        const float a = state.alpha[k][p];
        b[p] += frame.valid[p] * (1.0f - a) * (frame.rgb[c][p] - a * color);
      }
    }
    auto apply = [&](const float* x, float* y) {
      for (size_t p = 0; p < n; ++p) y[p] = data[p] * x[p];
      addLaplacian(grid, settings.lambda, x, y);
    };
    iterations[c] = solveConjugateGradient(apply, diagonal, b, state.background[c],
                                           settings.cgMaxIterations, settings.cgTolerance)
                        .iterations;
    for (float& s : state.background[c]) s = std::isfinite(s) ? std::max(0.0f, s) : 0.0f;
  });
  return *std::max_element(iterations, iterations + 3);
}

struct Energy {
  double objective = 0.0;  // per pixel per frame
  double dataRms = 0.0;
};

Energy evaluate(const Problem& problem, const State& state, const DerainSettings& settings) {
  const GridSize& grid = problem.grid;
  const size_t n = grid.count();
  const size_t frames = problem.frames.size();
  std::vector<double> data(frames, 0.0), samples(frames, 0.0), smoothAlpha(frames, 0.0);
  const cv::Vec2d d0 = streakDirection(state.angleDeg);
  forEachIndex(frames, [&](size_t k) {
    const PlanarFrame& frame = problem.frames[k];
    for (size_t p = 0; p < n; ++p) {
      if (frame.valid[p] == 0) continue;
      const float a = state.alpha[k][p];
      for (int c = 0; c < 3; ++c) {
        const double r =
            frame.rgb[c][p] - (1.0 - a) * state.background[c][p] - a * state.color[k][c];
        data[k] += r * r;
      }
      samples[k] += 3;
    }
    smoothAlpha[k] = directionalEnergy(grid, d0[0], d0[1], state.alpha[k].data());
  });
  double smoothS = 0.0;
  for (int c = 0; c < 3; ++c) smoothS += gradientEnergy(grid, state.background[c].data());
  double dataSum = 0.0, sampleSum = 0.0, alphaSum = 0.0;
  for (size_t k = 0; k < frames; ++k)
    dataSum += data[k], sampleSum += samples[k], alphaSum += smoothAlpha[k];
  Energy e;
  e.objective =
      (dataSum + settings.lambda * smoothS + settings.mu * alphaSum) / (double(n) * frames);
  e.dataRms = sampleSum > 0 ? std::sqrt(dataSum / sampleSum) : 0.0;
  return e;
}

// Back from code values to the FrameStack's 0..1.
cv::Mat planesToMat(const std::vector<float> (&planes)[3], const GridSize& grid) {
  cv::Mat out(grid.height, grid.width, CV_32FC3);
  for (int y = 0; y < grid.height; ++y) {
    cv::Vec3f* row = out.ptr<cv::Vec3f>(y);
    for (int x = 0; x < grid.width; ++x) {
      const size_t p = size_t(y) * grid.width + x;
      row[x] = cv::Vec3f(planes[0][p], planes[1][p], planes[2][p]) / kCodeValueScale;
    }
  }
  return out;
}

cv::Mat planeToMat(const std::vector<float>& plane, const GridSize& grid) {
  return cv::Mat(grid.height, grid.width, CV_32F, const_cast<float*>(plane.data())).clone();
}

void checkSettings(const DerainSettings& s) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw Error(fmt::format("rain extraction: {} must be a positive number, got {}", name, v),
                  {"derain"});
  };
  positive(s.lambda, "lambda");
  positive(s.mu, "mu");
  if (s.maxIterations < 0) throw Error("rain extraction: iterations must be 0 or more", {"derain"});
}

}  // namespace

cv::Mat temporalMedian(const FrameStack& stack) {
  const Problem problem = makeProblem(stack);
  std::vector<float> planes[3];
  for (int c = 0; c < 3; ++c) planes[c] = medianPlane(problem, c);
  return planesToMat(planes, problem.grid);
}

DerainResult solveDerain(const FrameStack& stack, const DerainSettings& settings) {
  checkSettings(settings);
  const auto started = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  };
  const Problem problem = makeProblem(stack);
  const size_t frames = problem.frames.size();
  const size_t n = problem.grid.count();

  State state;
  for (int c = 0; c < 3; ++c) state.background[c] = medianPlane(problem, c);
  state.alpha.assign(frames, std::vector<float>(n, 0.0f));
  for (const auto& frame : problem.frames) state.color.push_back(initialRainColor(problem, frame));
  state.angleDeg = foldRainAngleDeg(settings.initialAngleDeg);

  DerainResult result;
  result.noiseSigma = estimateNoiseSigma(problem, state);
  const std::vector<float> deadzone =
      alphaDeadzone(problem, state, result.noiseSigma, settings.registrationErrorPx);
  // D0 taken from the mattes' spectrum when its line stands out clearly there (else it keeps
  // its value): from the initialisation's residual first, then from each iteration's mattes.
  auto takeDirection = [&](const std::vector<cv::Mat>& mattes) {
    const RainAngleEstimate estimate = estimateRainAngle(mattes);
    if (estimate.salience >= kMinDirectionSalience &&
        estimate.agreement >= kMinDirectionAgreement) {
      state.angleDeg = estimate.angleDeg;
      result.angleFound = true;
    }
  };
  if (settings.estimateDirection) takeDirection(residualMattes(problem, state));
  Energy energy = evaluate(problem, state, settings);
  result.history.push_back(
      {0, energy.objective, energy.dataRms / kCodeValueScale, state.angleDeg, elapsed(), 0, 0});

  for (int iteration = 1; iteration <= settings.maxIterations; ++iteration) {
    std::vector<int> alphaIterations(frames, 0);
    forEachIndex(frames, [&](size_t k) {
      alphaIterations[k] = solveAlpha(problem, state, k, settings, deadzone, state.alpha[k]);
    });
    removePersistentAlpha(problem, state);
    if (settings.estimateDirection) takeDirection(transientMattes(problem, state));
    solveColor(problem, state);
    const int backgroundIterations = solveBackground(problem, state, settings);

    const Energy previous = energy;
    energy = evaluate(problem, state, settings);
    result.history.push_back(
        {iteration, energy.objective, energy.dataRms / kCodeValueScale, state.angleDeg, elapsed(),
         *std::max_element(alphaIterations.begin(), alphaIterations.end()), backgroundIterations});
    result.iterations = iteration;
    const double drop = previous.objective - energy.objective;
    if (iteration > 1 && drop <= settings.tolerance * std::max(previous.objective, 1e-30)) break;
  }

  result.background = planesToMat(state.background, problem.grid);
  for (const auto& alpha : state.alpha) result.alpha.push_back(planeToMat(alpha, problem.grid));
  for (const cv::Vec3f& color : state.color) result.rainColor.push_back(color / kCodeValueScale);
  result.angleDeg = state.angleDeg;
  result.residual = energy.dataRms / kCodeValueScale;
  result.noiseSigma /= kCodeValueScale;
  return result;
}

}  // namespace pluvia::derain
