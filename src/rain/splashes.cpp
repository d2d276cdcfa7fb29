#include "rain/splashes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "optics/drop_shading.h"
#include "optics/fresnel.h"
#include "rain/counter_stream.h"
#include "rain/depth_surface.h"
#include "util/parallel.h"

namespace pluvia::rain {
namespace {

// Constants of the splash's look (splashes.h).
constexpr double kCrownRadiusPerDiameter = 2.0, kCrownLifePerDropTime = 20.0;
constexpr double kDropletDiameterFraction = 0.15, kDropletSpeedFraction = 0.2;

double crownLifeSeconds(const Impact& impact) {
  return kCrownLifePerDropTime * impact.diameterMm * 1e-3 / impact.speedMetersPerSecond;
}

// z-depth at (px, py) on the surface: for a plane 1 / z is affine in the image, so 1 / z is
// interpolated bilinearly between the four nearest pixel centres; the nearest pixel's depth where
// one of them is missing or across a discontinuity.
double surfaceDepth(const std::vector<float>& depth, int w, int h, double px, double py) {
  // Beyond the outer pixel centres (the frame's border half pixels) 1 / z is extrapolated.
  const int x0 = std::clamp(int(std::floor(px - 0.5)), 0, std::max(w - 2, 0));
  const int y0 = std::clamp(int(std::floor(py - 0.5)), 0, std::max(h - 2, 0));
  const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
  const double fx = px - 0.5 - x0, fy = py - 0.5 - y0;
  auto at = [&](int x, int y) { return double(depth[size_t(y) * size_t(w) + size_t(x)]); };
  const double z00 = at(x0, y0), z10 = at(x1, y0), z01 = at(x0, y1), z11 = at(x1, y1);
  const double nearest = at(std::clamp(int(px), 0, w - 1), std::clamp(int(py), 0, h - 1));
  const double lo = std::min({z00, z10, z01, z11}), hi = std::max({z00, z10, z01, z11});
  if (!std::isfinite(hi) || !(lo > 0.0) || hi - lo > kDepthDiscontinuity * lo) return nearest;
  const double inverse =
      (1.0 - fy) * ((1.0 - fx) / z00 + fx / z10) + fy * ((1.0 - fx) / z01 + fx / z11);
  return inverse > 0.0 ? 1.0 / inverse : nearest;
}

}  // namespace

// The crown's patch directions on the horizontal, made once (no trigonometry per crown).
const std::array<Eigen::Vector3d, kCrownPoints>& crownDirections() {
  static const std::array<Eigen::Vector3d, kCrownPoints> directions = [] {
    std::array<Eigen::Vector3d, kCrownPoints> d;
    for (int k = 0; k < kCrownPoints; ++k) {
      const double phi = 2.0 * M_PI * (k + 0.5) / kCrownPoints;
      d[size_t(k)] = Eigen::Vector3d(std::cos(phi), 0.0, std::sin(phi));
    }
    return d;
  }();
  return directions;
}

namespace {

int dropletCount(const Impact& impact) {
  return 2 + int(std::lround(2.0 * impact.diameterMm));
}

}  // namespace

std::vector<float> upFacingAreaPerPixel(const Camera& camera, const std::vector<float>& depth,
                                        double maxTiltDeg, double maxDepthMeters) {
  const int w = camera.width, h = camera.height;
  std::vector<float> area(depth.size(), 0.0f);
  const double minUp = std::cos(maxTiltDeg * M_PI / 180.0);
  forEachRow(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      // Forward differences, backward at the last column and row.
      const int dx = x + 1 < w ? 1 : -1, dy = y + 1 < h ? 1 : -1;
      const double z = depth[i];
      if (!(z <= maxDepthMeters)) continue;
      const double zx = depth[i + size_t(dx)], zy = depth[i + size_t(dy) * size_t(w)];
      if (!depthsContinuous(z, zx) || !depthsContinuous(z, zy)) continue;
      const Eigen::Vector3d p = worldPoint(camera, x + 0.5, y + 0.5, z);
      const Eigen::Vector3d ex = (worldPoint(camera, x + 0.5 + dx, y + 0.5, zx) - p) * dx;
      const Eigen::Vector3d ey = (worldPoint(camera, x + 0.5, y + 0.5 + dy, zy) - p) * dy;
      const Eigen::Vector3d n = ex.cross(ey);  // |n| = the footprint's area
      const double a = n.norm();
      if (a > 0.0 && std::abs(n.y()) >= minUp * a) area[i] = float(std::abs(n.y()));
    }
  });
  return area;
}

SplashTiles splashTiles(const SplashField& field, int width, int height) {
  SplashTiles tiles;
  const int t = field.tilePx;
  tiles.tilesX = (width + t - 1) / t;
  tiles.tilesY = (height + t - 1) / t;
  tiles.cumulativeArea.resize(static_cast<size_t>(tiles.tilesX) * tiles.tilesY);
  forEachRow(tiles.tilesY, [&](int ty) {
    for (int tx = 0; tx < tiles.tilesX; ++tx) {
      const int x0 = tx * t, y0 = ty * t, x1 = std::min(width, x0 + t),
                y1 = std::min(height, y0 + t);
      std::vector<double> cumulative;
      double total = 0.0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
          cumulative.push_back(total += field.areaPerPixel[size_t(y) * size_t(width) + size_t(x)]);
      if (total > 0.0)
        tiles.cumulativeArea[size_t(ty) * size_t(tiles.tilesX) + size_t(tx)] =
            std::move(cumulative);
    }
  });
  return tiles;
}

std::vector<Impact> impactsBorn(const SplashField& field, const SplashTiles& tiles,
                                const Camera& camera, int64_t birthFrame, double fps, uint64_t seed,
                                const ImpactDiameters& diameters, VelocityModel velocity) {
  const int w = camera.width, h = camera.height, t = field.tilePx;
  // Rows of tiles in parallel: each tile's impacts depend on its own generator alone, and the
  // rows are joined in their order, so the list is the same whatever the thread count.
  std::vector<std::vector<Impact>> rows(static_cast<size_t>(tiles.tilesY));
  forEachRow(tiles.tilesY, [&](int ty) {
    std::vector<Impact>& impacts = rows[size_t(ty)];
    for (int tx = 0; tx < tiles.tilesX; ++tx) {
      const uint64_t tile = uint64_t(ty) * uint64_t(tiles.tilesX) + uint64_t(tx);
      const std::vector<double>& cumulative = tiles.cumulativeArea[tile];
      if (cumulative.empty()) continue;
      const double total = cumulative.back();
      const int x0 = tx * t, x1 = std::min(w, x0 + t);
      Stream rng{mix(seed ^ mix(uint64_t(birthFrame) * 0x100000001b3ULL ^ mix(tile)))};
      const int n = rng.poisson(total * field.impactsPerSquareMeterSecond / fps);
      for (int k = 0; k < n; ++k) {
        const double pick = rng.uniform() * total;
        const size_t j = size_t(std::lower_bound(cumulative.begin(), cumulative.end(), pick) -
                                cumulative.begin());
        const int x = x0 + int(std::min(j, cumulative.size() - 1)) % (x1 - x0);
        const int y = ty * t + int(std::min(j, cumulative.size() - 1)) / (x1 - x0);
        const double px = x + rng.uniform(), py = y + rng.uniform();
        Impact impact;
        impact.point = worldPoint(camera, px, py, surfaceDepth(field.depth, w, h, px, py));
        impact.timeSeconds = (double(birthFrame) + rng.uniform()) / fps;
        impact.diameterMm = diameters.sampleMm(rng.uniform());
        impact.speedMetersPerSecond = terminalVelocity(velocity, impact.diameterMm);
        impact.key = mix(rng.state);
        impacts.push_back(impact);
      }
    }
  });
  std::vector<Impact> impacts;
  for (const std::vector<Impact>& row : rows) impacts.insert(impacts.end(), row.begin(), row.end());
  return impacts;
}

std::vector<Impact> impactsBorn(const SplashField& field, const Camera& camera, int64_t birthFrame,
                                double fps, uint64_t seed, const ImpactDiameters& diameters,
                                VelocityModel velocity) {
  return impactsBorn(field, splashTiles(field, camera.width, camera.height), camera, birthFrame,
                     fps, seed, diameters, velocity);
}

double splashLifeSeconds(const Impact& impact) {
  // The steepest droplet (75 deg) flies longest.
  const double up =
      kDropletSpeedFraction * impact.speedMetersPerSecond * std::sin(75.0 * M_PI / 180.0);
  return std::max(crownLifeSeconds(impact), 2.0 * up / kGravity);
}

double dropletDiameterMeters(const Impact& impact) {
  return kDropletDiameterFraction * impact.diameterMm * 1e-3;
}

double dropletReachMeters(const Impact& impact) {
  // Range at most v^2 / g (at 45 deg), height at most v^2 / (2 g): within 1.12 v^2 / g.
  const double v = kDropletSpeedFraction * impact.speedMetersPerSecond;
  return 1.2 * v * v / kGravity;
}

void appendSplashParticles(const Impact& impact, double open, double close, double pixelMeters,
                           std::vector<SplashParticle>& out, bool droplets) {
  const double d = impact.diameterMm * 1e-3;
  // Crown: a rim growing as sqrt(age), standing D tall.
  const double crownLife = crownLifeSeconds(impact);
  const double a0 = std::max(open - impact.timeSeconds, 0.0);
  const double a1 = std::min(close - impact.timeSeconds, crownLife);
  const double rMax = kCrownRadiusPerDiameter * d;
  const Eigen::Vector3d centre = impact.point + Eigen::Vector3d(0, 0.5 * d, 0);
  if (a1 > a0) {
    const double r0 = rMax * std::sqrt(a0 / crownLife), r1 = rMax * std::sqrt(a1 / crownLife);
    // The sheet as the camera sees it: two walls (near and far) 2 r wide and D tall, r at the
    // middle of the exposure, shared by the patches as discs of the same area.
    const double patchArea = 4.0 * 0.5 * (r0 + r1) * d / kCrownPoints;
    const double patchDiameter = std::sqrt(4.0 * patchArea / M_PI);
    if (2.0 * rMax < pixelMeters) {
      SplashParticle merged{centre, centre, std::sqrt(double(kCrownPoints)) * patchDiameter};
      merged.crownMerged = true;
      out.push_back(merged);
    } else {
      for (const Eigen::Vector3d& dir : crownDirections())
        out.push_back({centre + dir * r0, centre + dir * r1, patchDiameter, dir});
    }
  }
  // Droplets: ballistic until they are back at the surface.
  if (!droplets) return;
  Stream rng{impact.key};
  const int n = dropletCount(impact);
  const double speed = kDropletSpeedFraction * impact.speedMetersPerSecond;
  for (int k = 0; k < n; ++k) {
    const double phi = 2.0 * M_PI * rng.uniform();
    const double elevation = (45.0 + 30.0 * rng.uniform()) * M_PI / 180.0;
    const double up = speed * std::sin(elevation);
    const double flight = 2.0 * up / kGravity;
    const double b0 = std::max(open - impact.timeSeconds, 0.0);
    const double b1 = std::min(close - impact.timeSeconds, flight);
    if (!(b1 > b0)) continue;  // landed before the shutter opened: no azimuth needed
    const double across = speed * std::cos(elevation);
    const Eigen::Vector3d v0(across * std::cos(phi), up, across * std::sin(phi));
    auto at = [&](double age) -> Eigen::Vector3d {
      return impact.point + v0 * age + Eigen::Vector3d(0, -0.5 * kGravity * age * age, 0);
    };
    out.push_back({at(b0), at(b1), kDropletDiameterFraction * d});
  }
}

SheetReflection crownSheetReflection(const Eigen::Vector3d& outward,
                                     const Eigen::Vector3d& towardsCamera) {
  const double lean = kCrownLeanDeg * M_PI / 180.0;
  // The outer face's normal: outwards and down, perpendicular to the leaning sheet.
  Eigen::Vector3d normal = outward * std::cos(lean) - Eigen::Vector3d::UnitY() * std::sin(lean);
  double cosIncidence = normal.dot(towardsCamera);
  if (cosIncidence < 0.0) normal = -normal, cosIncidence = -cosIncidence;  // the inner face
  SheetReflection result;
  result.mirrorDirection = (2.0 * cosIncidence * normal - towardsCamera).normalized();
  const double r = optics::fresnelReflectance(std::min(cosIncidence, 1.0), optics::kWaterEta);
  result.reflectance = 2.0 * r / (1.0 + r);
  return result;
}

std::vector<SplashParticle> splashParticles(const Impact& impact, double open, double close,
                                            double pixelMeters) {
  std::vector<SplashParticle> particles;
  appendSplashParticles(impact, open, close, pixelMeters, particles);
  return particles;
}

}  // namespace pluvia::rain
