// Placed frames rendered into an equirect map: exposure gains matched on the overlaps, a
// feathered mean per texel, nearest-colour fill of the unseen directions, light sources.
#include <tbb/combinable.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "envmap/panorama.h"
#include "envmap/unseen_fill.h"
#include "util/parallel.h"

namespace pluvia::envmap {
namespace {

struct FrameView {
  cv::Matx33d worldToCamera;
  double f = 1.0;
  int w = 0, h = 0;
  const cv::Mat* rgb = nullptr;
  const cv::Mat* saturated = nullptr;  // may be empty
};

struct Sample {
  cv::Vec3f rgb;
  float weight = 0.0f;
  bool saturated = false;
  int x = 0, y = 0;  // nearest pixel
};

// Projects a world direction into a frame; false when the frame does not see it.
bool project(const FrameView& v, const cv::Vec3d& dir, double& px, double& py) {
  const cv::Vec3d c = v.worldToCamera * dir;
  if (c[2] >= -1e-6) return false;  // behind the camera (it looks along -Z)
  const double inv = 1.0 / -c[2];
  px = v.f * c[0] * inv + 0.5 * v.w;  // continuous image coordinates, 0..w
  py = -v.f * c[1] * inv + 0.5 * v.h;
  return px >= 0.0 && px <= v.w && py >= 0.0 && py <= v.h;
}

// Bilinear sample between pixel centres, with the feather weight (distance to the border,
// normalised by half the shorter side) and whether any of the four pixels is saturated.
Sample sampleFrame(const FrameView& v, double px, double py) {
  Sample s;
  const double border = std::min(std::min(px, v.w - px), std::min(py, v.h - py));
  s.weight = float(std::max(border, 1e-3) / (0.5 * std::min(v.w, v.h)));
  const double sx = std::clamp(px - 0.5, 0.0, double(v.w - 1));
  const double sy = std::clamp(py - 0.5, 0.0, double(v.h - 1));
  const int x0 = int(sx), y0 = int(sy);
  const int x1 = std::min(x0 + 1, v.w - 1), y1 = std::min(y0 + 1, v.h - 1);
  const float fx = float(sx - x0), fy = float(sy - y0);
  const auto* r0 = v.rgb->ptr<cv::Vec3f>(y0);
  const auto* r1 = v.rgb->ptr<cv::Vec3f>(y1);
  s.rgb = (r0[x0] * (1 - fx) + r0[x1] * fx) * (1 - fy) + (r1[x0] * (1 - fx) + r1[x1] * fx) * fy;
  if (!v.saturated->empty()) {
    const auto* m0 = v.saturated->ptr<uchar>(y0);
    const auto* m1 = v.saturated->ptr<uchar>(y1);
    s.saturated = m0[x0] || m0[x1] || m1[x0] || m1[x1];
  }
  s.x = std::clamp(int(px), 0, v.w - 1);
  s.y = std::clamp(int(py), 0, v.h - 1);
  return s;
}

cv::Vec3d texelDirection(int width, int height, int x, int y) {
  const auto d = equirectTexelDirection(width, height, x, y);
  return {d[0], d[1], d[2]};
}

float meanOf(const cv::Vec3f& c) {
  return (c[0] + c[1] + c[2]) / 3.0f;
}

// Per-frame exposure gains from the overlaps: on a coarse grid, the mean intensity of frame i
// and of frame j where both see a direction unsaturated; then least squares in log space,
//   sum_ij N_ij (log g_i + log I_ij - log g_j - log I_ji)^2 + lambda sum_i (log g_i)^2,
// with g_0 = 1 (lambda small: it only fixes frames without overlaps at 1).
std::vector<float> estimateGains(const std::vector<FrameView>& views) {
  const int n = int(views.size());
  std::vector<float> gains(n, 1.0f);
  if (n < 2) return gains;
  const int gw = 256, gh = 128;
  struct Acc {
    std::vector<double> sum;    // n*n: sum over overlap texels of frame i's intensity (i,j)
    std::vector<double> count;  // n*n
  };
  tbb::combinable<Acc> accs([n] {
    return Acc{std::vector<double>(n * n), std::vector<double>(n * n)};
  });
  forEachRow(gh, [&](int y) {
    Acc& acc = accs.local();
    std::vector<int> seen;
    std::vector<float> value;
    for (int x = 0; x < gw; ++x) {
      const cv::Vec3d dir = texelDirection(gw, gh, x, y);
      seen.clear();
      value.clear();
      for (int k = 0; k < n; ++k) {
        double px, py;
        if (!project(views[k], dir, px, py)) continue;
        const Sample s = sampleFrame(views[k], px, py);
        const float m = meanOf(s.rgb);
        if (s.saturated || !(m > 1e-4f) || !std::isfinite(m)) continue;
        seen.push_back(k);
        value.push_back(m);
      }
      for (std::size_t a = 0; a < seen.size(); ++a)
        for (std::size_t b = 0; b < seen.size(); ++b) {
          if (a == b) continue;
          acc.sum[seen[a] * n + seen[b]] += value[a];
          acc.count[seen[a] * n + seen[b]] += 1.0;
        }
    }
  });
  Acc total{std::vector<double>(n * n), std::vector<double>(n * n)};
  accs.combine_each([&](const Acc& a) {
    for (int i = 0; i < n * n; ++i) {
      total.sum[i] += a.sum[i];
      total.count[i] += a.count[i];
    }
  });
  // Unknowns: log g_1 .. log g_{n-1}.
  const int m = n - 1;
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(m, m) * 1e-3;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(m);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const double nij = total.count[i * n + j];
      if (nij < 4) continue;
      const double iij = total.sum[i * n + j] / nij;  // frame i's mean on the overlap
      const double iji = total.sum[j * n + i] / nij;  // frame j's mean on the overlap
      if (iij <= 0 || iji <= 0) continue;
      // Residual: log g_i - log g_j - (log I_ji - log I_ij).
      const double rhs = std::log(iji) - std::log(iij);
      const int ui = i - 1, uj = j - 1;
      if (ui >= 0) {
        A(ui, ui) += nij;
        b(ui) += nij * rhs;
      }
      if (uj >= 0) {
        A(uj, uj) += nij;
        b(uj) -= nij * rhs;
      }
      if (ui >= 0 && uj >= 0) {
        A(ui, uj) -= nij;
        A(uj, ui) -= nij;
      }
    }
  const Eigen::VectorXd logG = A.ldlt().solve(b);
  for (int k = 1; k < n; ++k) {
    const double g = std::exp(logG(k - 1));
    gains[k] = std::isfinite(g) ? float(std::clamp(g, 0.1, 10.0)) : 1.0f;
  }
  return gains;
}

// The sun for the sky model, from the lights: the brightest light above the horizon, a
// direction light's direction or the mean direction of the texels a frame-region light covers.
std::optional<Vec3> sunFromLights(const std::vector<LightSource>& lights,
                                  const std::vector<const LightSource*>& texelLight, int width,
                                  int height) {
  std::optional<Vec3> sun;
  double brightest = 0.0;
  auto consider = [&](const LightSource& light, cv::Vec3d d) {
    const double power = meanOf(cv::Vec3f(light.radiance[0], light.radiance[1], light.radiance[2]));
    const double len = cv::norm(d);
    if (!(len > 0) || d[1] <= 0 || power <= brightest) return;
    d /= len;
    sun = Vec3{d[0], d[1], d[2]};
    brightest = power;
  };
  std::vector<cv::Vec3d> regionSum(lights.size(), cv::Vec3d(0, 0, 0));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (const LightSource* l = texelLight[size_t(y) * size_t(width) + size_t(x)])
        regionSum[size_t(l - lights.data())] += texelDirection(width, height, x, y);
  for (size_t i = 0; i < lights.size(); ++i) {
    const LightSource& light = lights[i];
    if (light.direction)
      consider(light, {(*light.direction)[0], (*light.direction)[1], (*light.direction)[2]});
    else
      consider(light, regionSum[i]);
  }
  return sun;
}

}  // namespace

PanoramaResult renderEquirect(const std::vector<PanoramaFrame>& frames, const Placement& placement,
                              const EquirectSettings& settings) {
  PanoramaResult result;
  const int width = std::max(2, settings.width - settings.width % 2);
  const int height = width / 2;
  result.radiance = EquirectMap(width, height);
  result.coverage = cv::Mat(height, width, CV_8UC1, cv::Scalar(0));
  // Seen only through clipped pixels: a lower bound, kept out of the sky model's fit.
  cv::Mat clipped(height, width, CV_8UC1, cv::Scalar(0));
  // The frame-region light a texel's saturated pixel lies in; applied after the fill, so the
  // unseen directions take the footage's colours, not copies of a light (which would multiply
  // its power).
  std::vector<const LightSource*> texelLight(size_t(width) * size_t(height), nullptr);

  static const cv::Mat kNoMask;
  std::vector<FrameView> views;
  std::vector<int> viewFrame;  // frame index of each view
  const int n = int(std::min(frames.size(), placement.poses.size()));
  for (int k = 0; k < n; ++k) {
    const auto& f = frames[k];
    if (f.linearRgb.empty() || f.linearRgb.type() != CV_32FC3) continue;
    FrameView v;
    v.worldToCamera = placement.poses[k].cameraToWorld.t();
    v.w = f.linearRgb.cols;
    v.h = f.linearRgb.rows;
    v.f = placement.poses[k].focalPx > 0 ? placement.poses[k].focalPx : double(v.w);
    v.rgb = &f.linearRgb;
    v.saturated = (f.saturated.size() == f.linearRgb.size() && f.saturated.type() == CV_8UC1)
                      ? &f.saturated
                      : &kNoMask;
    views.push_back(v);
    viewFrame.push_back(k);
  }
  const std::vector<float> viewGains = estimateGains(views);
  result.gains.assign(frames.size(), 1.0f);
  for (std::size_t i = 0; i < views.size(); ++i) result.gains[viewFrame[i]] = viewGains[i];

  // Frame-region lights, by view index.
  std::vector<std::vector<const LightSource*>> regionLights(views.size());
  for (const auto& light : settings.lights) {
    if (light.direction || light.frame < 0) continue;
    for (std::size_t i = 0; i < views.size(); ++i)
      if (viewFrame[i] == light.frame) regionLights[i].push_back(&light);
  }

  forEachRow(height, [&](int y) {
    uchar* cov = result.coverage.ptr<uchar>(y);
    for (int x = 0; x < width; ++x) {
      const cv::Vec3d dir = texelDirection(width, height, x, y);
      cv::Vec3d sum(0, 0, 0), satSum(0, 0, 0);
      double weight = 0, satWeight = 0;
      const LightSource* hitLight = nullptr;
      for (std::size_t i = 0; i < views.size(); ++i) {
        double px, py;
        if (!project(views[i], dir, px, py)) continue;
        const Sample s = sampleFrame(views[i], px, py);
        if (s.saturated) {
          for (const LightSource* l : regionLights[i])
            if (l->region.contains(cv::Point(s.x, s.y))) hitLight = l;
          satSum += cv::Vec3d(s.rgb) * double(viewGains[i]) * double(s.weight);
          satWeight += s.weight;
        } else {
          sum += cv::Vec3d(s.rgb) * double(viewGains[i]) * double(s.weight);
          weight += s.weight;
        }
      }
      float* out = result.radiance.texel(x, y);
      texelLight[size_t(y) * size_t(width) + size_t(x)] = hitLight;
      if (weight > 0) {
        // Unsaturated samples are the measurement; clipped ones only a lower bound.
        for (int c = 0; c < 3; ++c) out[c] = float(sum[c] / weight);
      } else if (satWeight > 0) {
        for (int c = 0; c < 3; ++c) out[c] = float(satSum[c] / satWeight);  // keeps its clip
      }
      if (weight > 0 || satWeight > 0 || hitLight) cov[x] = 255;
      if (weight <= 0 && (satWeight > 0 || hitLight)) clipped.at<uchar>(y, x) = 255;
    }
  });

  double covered = 0.0;
  for (int y = 0; y < height; ++y) {
    const int count = cv::countNonZero(result.coverage.row(y));
    covered += count * equirectTexelSolidAngle(width, height, y);
  }
  result.coveredFraction = covered / (4.0 * CV_PI);
  result.fillModel = "nearest";
  if (covered > 0) {
    const std::vector<int> nearest = nearestSeenTexels(result.coverage);
    ModelFillSettings model;
    model.sun = sunFromLights(settings.lights, texelLight, width, height);
    if (!(settings.fill == UnseenFill::SkyModel &&
          fillModel(result.radiance, result.coverage, clipped, nearest, model, result.fillModel)))
      fillNearest(result.radiance, result.coverage, nearest);
  }
  // A saturated pixel inside a frame's light region: the light's measured radiance.
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (const LightSource* l = texelLight[size_t(y) * size_t(width) + size_t(x)]) {
        float* out = result.radiance.texel(x, y);
        for (int c = 0; c < 3; ++c) out[c] = l->radiance[c];
      }

  // Direction lights: their radiance is measured, so every texel whose centre lies within the
  // disc takes it, seen or not, saturated or not (the footage only bounds it from below). A disc
  // smaller than a texel that holds no texel centre gives the texel containing its centre the
  // disc's power: a blend by the ratio of solid angles.
  for (const auto& light : settings.lights) {
    if (!light.direction) continue;
    cv::Vec3d d((*light.direction)[0], (*light.direction)[1], (*light.direction)[2]);
    const double len = cv::norm(d);
    if (!(len > 0)) continue;
    d /= len;
    const double radius = std::max(0.0, light.radiusDeg) * CV_PI / 180.0;
    const double cosR = std::cos(radius);
    // Rows that can hold the disc.
    const double theta = std::acos(std::clamp(d[1], -1.0, 1.0));
    const int y0 =
        std::clamp(int(std::floor((theta - radius) / CV_PI * height)) - 1, 0, height - 1);
    const int y1 = std::clamp(int(std::ceil((theta + radius) / CV_PI * height)) + 1, 0, height - 1);
    bool any = false;
    for (int y = y0; y <= y1; ++y)
      for (int x = 0; x < width; ++x) {
        if (texelDirection(width, height, x, y).dot(d) < cosR) continue;
        float* out = result.radiance.texel(x, y);
        for (int c = 0; c < 3; ++c) out[c] = light.radiance[c];
        any = true;
      }
    if (!any) {
      const auto uv = equirectUv({d[0], d[1], d[2]});
      const int x = std::clamp(int(uv[0] * width), 0, width - 1);
      const int y = std::clamp(int(uv[1] * height), 0, height - 1);
      const double disc = 2.0 * CV_PI * (1.0 - cosR);
      const float a = float(std::clamp(disc / equirectTexelSolidAngle(width, height, y), 0.0, 1.0));
      float* out = result.radiance.texel(x, y);
      for (int c = 0; c < 3; ++c) out[c] = (1 - a) * out[c] + a * light.radiance[c];
    }
  }
  return result;
}

}  // namespace pluvia::envmap
