#include "stages/local_lights.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "util/error.h"

namespace pluvia {
namespace {

constexpr int kTilePx = 16;
// A lit tile is interpolated from its corners when its scene is one smooth surface (1/z within 5 %
// of bilinear) and its corners glow within 25 % of each other (addHalos). The glow falls as about
// 1 / distance from the light's image: bilinear across a 25 % step errs by about 1 % of the value
// there (0.1 % of the peak on the test frame against every pixel; 10 % gave 0.04 % at 2.6 times
// the evaluations).
constexpr double kSmoothDepth = 0.05;
constexpr double kSmoothGlow = 0.25;
// A light's glow is interpolated too where its corners differ by less than this fraction of all
// the lights' glow there (a beam's edge, where bilinear may err by half that difference, under
// the glow of other lamps). 2 % gave 6.2 % at the worst pixel of the 100-light halo frame, 1 %
// 6.0 %, none 5.8 %; 0.5 % cost twice the time of 1 %.
constexpr double kSumGlow = 0.01;
// At a depth edge, at most this many depth steps per corner (a tile spanning more than
// 1.05^24 = 3.2 times in depth gets coarser steps).
constexpr int kMaxDepthSteps = 24;
// A tile whose glow turns fast is split into sub-tiles of this size, interpolated alike.
constexpr int kSubTilePx = 4;
// Around a light's image every pixel is evaluated this far from it (its peak lies between any
// samples): one sub-tile gave 8.4 % at the worst pixel of the 100-light halo frame, two 6.2 %,
// the same as every pixel of the 3 x 3 tiles around it. Beyond the bulb's own image (its disc's
// edge is sharp: a near lamp's disc 12 px across erred by 5 % at its rim with this alone).
constexpr int kPeakPx = 2 * kSubTilePx;
// Each light's glow on the grid of tile corners is itself found coarse to fine: on cells of 8, 4
// and 2 tiles a side, a cell whose scene is one smooth surface (every grid point's 1/z within
// kSmoothDepth of bilinear, no depth edge), away from the light's image, whose corners glow
// within kCoarseGlow of each other and whose centre is within kCoarseCentre of its corners'
// bilinear value takes its grid points bilinearly; any other cell is split. Far from a light its
// halo turns slowly, and most of its grid is never evaluated (100 lights over a 1080p frame:
// 8.3k evaluations each before).
constexpr std::array<int, 3> kCoarseCells{8, 4, 2};  // grid cells a side, coarsest first
constexpr double kCoarseGlow = 0.25;
constexpr double kCoarseCentre = 0.005;

optics::Vec3 unitRay(const Camera& camera, double px, double py, double& lengthPerDepth) {
  const Eigen::Vector3d r = camera.rayCamera(px, py);
  lengthPerDepth = r.norm();  // r has z = -1: the ray's length per metre of z-depth
  const Eigen::Vector3d u = r / lengthPerDepth;
  return {u.x(), u.y(), u.z()};
}

double maxChannel(const std::array<double, 3>& rgb) {
  return std::max({rgb[0], rgb[1], rgb[2]});
}

// The grid of tile corners as the coarse-to-fine evaluation sees it: its points' pixels, and per
// coarse level (kCoarseCells) which cells are one smooth surface. Once per frame.
struct CornerGrid {
  int w = 0, h = 0;
  std::vector<int> px, py;  // the points' pixel columns and rows
  std::array<std::vector<uint8_t>, kCoarseCells.size()> smooth;
  int cellsX(size_t level) const { return (w - 1 + kCoarseCells[level] - 1) / kCoarseCells[level]; }
  int cellsY(size_t level) const { return (h - 1 + kCoarseCells[level] - 1) / kCoarseCells[level]; }
};

// `inverseDepth`: 1/z at each point (0: the sky); `atEdge`: the points at a depth edge.
CornerGrid cornerGrid(std::vector<int> px, std::vector<int> py,
                      const std::vector<double>& inverseDepth, const std::vector<uint8_t>& atEdge) {
  CornerGrid grid;
  grid.w = int(px.size()), grid.h = int(py.size());
  grid.px = std::move(px), grid.py = std::move(py);
  for (size_t level = 0; level < kCoarseCells.size(); ++level) {
    const int s = kCoarseCells[level], cellsX = grid.cellsX(level), cellsY = grid.cellsY(level);
    std::vector<uint8_t>& smooth = grid.smooth[level];
    smooth.assign(static_cast<size_t>(cellsX) * cellsY, 1);
    for (int cy = 0; cy < cellsY; ++cy)
      for (int cx = 0; cx < cellsX; ++cx) {
        const int ix0 = cx * s, ix1 = std::min(ix0 + s, grid.w - 1);
        const int iy0 = cy * s, iy1 = std::min(iy0 + s, grid.h - 1);
        auto at = [&](int i, int j) { return static_cast<size_t>(j) * grid.w + i; };
        const double ex = std::max(1, grid.px[size_t(ix1)] - grid.px[size_t(ix0)]);
        const double ey = std::max(1, grid.py[size_t(iy1)] - grid.py[size_t(iy0)]);
        bool ok = true;
        for (int j = iy0; j <= iy1 && ok; ++j)
          for (int i = ix0; i <= ix1 && ok; ++i) {
            const double u = (grid.px[size_t(i)] - grid.px[size_t(ix0)]) / ex;
            const double v = (grid.py[size_t(j)] - grid.py[size_t(iy0)]) / ey;
            const double plane =
                (1 - v) * ((1 - u) * inverseDepth[at(ix0, iy0)] + u * inverseDepth[at(ix1, iy0)]) +
                v * ((1 - u) * inverseDepth[at(ix0, iy1)] + u * inverseDepth[at(ix1, iy1)]);
            const double here = inverseDepth[at(i, j)];
            ok =
                !atEdge[at(i, j)] && std::abs(here - plane) <= kSmoothDepth * std::max(here, plane);
          }
        smooth[static_cast<size_t>(cy) * cellsX + cx] = ok;
      }
  }
  return grid;
}

// One light's glow at every grid point, coarse to fine (kCoarseCells): `evaluate(g)` at the
// points it needs, bilinear from a cell's corners elsewhere. (lightPx, lightPy): the light's
// image (far outside the frame when behind the camera). A spot's cell whose corners are all dark
// is taken as dark only when the corners of its 8 neighbours are too (a beam narrower than three
// cells passing between all their corners is missed, as the tiles miss one narrower than three
// tiles). Returns the evaluations done.
template <class Evaluate>
size_t glowCoarseToFine(const CornerGrid& grid, double lightPx, double lightPy, bool spot,
                        bool everyPoint, const Evaluate& evaluate, std::vector<double>& glow) {
  const size_t count = static_cast<size_t>(grid.w) * grid.h;
  std::vector<uint8_t> known(count, 0);
  std::vector<size_t> todo;
  size_t evaluations = 0;
  auto at = [&](int i, int j) { return static_cast<size_t>(j) * grid.w + i; };
  auto request = [&](int i, int j) {
    const size_t g = at(i, j);
    if (!known[g]) known[g] = 1, todo.push_back(g);
  };
  auto run = [&]() {
    tbb::parallel_for(size_t(0), todo.size(), [&](size_t k) { glow[todo[k]] = evaluate(todo[k]); });
    evaluations += todo.size();
    todo.clear();
  };
  if (everyPoint) {
    for (int j = 0; j < grid.h; ++j)
      for (int i = 0; i < grid.w; ++i) request(i, j);
    run();
    return evaluations;
  }
  struct Cell {
    int cx, cy;
  };
  std::vector<Cell> active;
  {
    const int s = kCoarseCells[0];
    for (int cy = 0; cy < grid.cellsY(0); ++cy)
      for (int cx = 0; cx < grid.cellsX(0); ++cx) {
        active.push_back({cx, cy});
        request(cx * s, cy * s);
        request(std::min(cx * s + s, grid.w - 1), cy * s);
        request(cx * s, std::min(cy * s + s, grid.h - 1));
        request(std::min(cx * s + s, grid.w - 1), std::min(cy * s + s, grid.h - 1));
      }
    run();
  }
  for (size_t level = 0; level < kCoarseCells.size(); ++level) {
    const int s = kCoarseCells[level], half = s / 2;
    const int cellsX = grid.cellsX(level), cellsY = grid.cellsY(level);
    auto bounds = [&](const Cell& c) {
      return std::array<int, 4>{c.cx * s, std::min(c.cx * s + s, grid.w - 1), c.cy * s,
                                std::min(c.cy * s + s, grid.h - 1)};
    };
    // A spot's dark cell: dark too at every corner of its neighbours (all known at this level).
    auto neighboursDark = [&](const Cell& c) {
      for (int j = std::max(0, c.cy - 1); j <= std::min(cellsY, c.cy + 2); ++j)
        for (int i = std::max(0, c.cx - 1); i <= std::min(cellsX, c.cx + 2); ++i)
          if (glow[at(std::min(i * s, grid.w - 1), std::min(j * s, grid.h - 1))] > 0.0)
            return false;
      return true;
    };
    // Whether each cell may be interpolated from its corners, its centre asked for.
    std::vector<uint8_t> candidate(active.size(), 0);
    for (size_t k = 0; k < active.size(); ++k) {
      const Cell& c = active[k];
      const auto [ix0, ix1, iy0, iy1] = bounds(c);
      const double margin = double(s * kTilePx);
      const bool nearLight =
          lightPx >= grid.px[size_t(ix0)] - margin && lightPx <= grid.px[size_t(ix1)] + margin &&
          lightPy >= grid.py[size_t(iy0)] - margin && lightPy <= grid.py[size_t(iy1)] + margin;
      if (nearLight || !grid.smooth[level][static_cast<size_t>(c.cy) * cellsX + c.cx]) continue;
      const std::array<double, 4> corner{glow[at(ix0, iy0)], glow[at(ix1, iy0)], glow[at(ix0, iy1)],
                                         glow[at(ix1, iy1)]};
      const auto [lo, hi] = std::minmax_element(corner.begin(), corner.end());
      if (*lo > 0.0 ? *hi <= *lo * (1.0 + kCoarseGlow) : *hi <= 0.0 && (!spot || neighboursDark(c)))
        candidate[k] = 1, request((ix0 + ix1) / 2, (iy0 + iy1) / 2);
    }
    run();
    std::vector<Cell> next;
    for (size_t k = 0; k < active.size(); ++k) {
      const Cell& c = active[k];
      const auto [ix0, ix1, iy0, iy1] = bounds(c);
      const double ex = std::max(1, grid.px[size_t(ix1)] - grid.px[size_t(ix0)]);
      const double ey = std::max(1, grid.py[size_t(iy1)] - grid.py[size_t(iy0)]);
      auto bilinear = [&](int i, int j) {
        const double u = (grid.px[size_t(i)] - grid.px[size_t(ix0)]) / ex;
        const double v = (grid.py[size_t(j)] - grid.py[size_t(iy0)]) / ey;
        return (1 - v) * ((1 - u) * glow[at(ix0, iy0)] + u * glow[at(ix1, iy0)]) +
               v * ((1 - u) * glow[at(ix0, iy1)] + u * glow[at(ix1, iy1)]);
      };
      if (candidate[k]) {
        const int mx = (ix0 + ix1) / 2, my = (iy0 + iy1) / 2;
        const double centre = glow[at(mx, my)], predicted = bilinear(mx, my);
        if (std::abs(centre - predicted) <= kCoarseCentre * centre) {
          for (int j = iy0; j <= iy1; ++j)
            for (int i = ix0; i <= ix1; ++i)
              if (!known[at(i, j)]) glow[at(i, j)] = bilinear(i, j);
          continue;
        }
      }
      // Split: its points at half its step (every point at the last level), its sub-cells next.
      for (int j = iy0; j <= iy1; j = j == iy1 ? j + 1 : std::min(j + half, iy1))
        for (int i = ix0; i <= ix1; i = i == ix1 ? i + 1 : std::min(i + half, ix1)) request(i, j);
      if (half > 1)
        for (int j = iy0; j < iy1; j += half)
          for (int i = ix0; i < ix1; i += half) next.push_back({i / half, j / half});
    }
    run();
    active = std::move(next);
  }
  return evaluations;
}

}  // namespace

std::vector<FrameLight> lightsAtFrame(const LightsSettings& settings, const Camera& camera,
                                      double frame) {
  std::vector<FrameLight> out;
  const Eigen::Matrix3d cameraFromWorld = camera.worldFromCamera.transpose();
  for (size_t i = 0; i < settings.lights.size(); ++i) {
    const LightSpec& spec = settings.lights[i];
    FrameLight light;
    Eigen::Vector3d position(spec.xMeters.valueAt(frame), spec.yMeters.valueAt(frame),
                             spec.zMeters.valueAt(frame));
    Eigen::Vector3d axis(spec.direction[0], spec.direction[1], spec.direction[2]);
    if (spec.worldFrame) {
      position = cameraFromWorld * (position - camera.positionMeters);
      axis = cameraFromWorld * axis;
    }
    const double intensity = spec.intensity.valueAt(frame);
    for (int c = 0; c < 3; ++c) light.rgbIntensity[size_t(c)] = intensity * spec.rgb[size_t(c)];
    light.positionMeters = {position.x(), position.y(), position.z()};
    light.radiusMeters = spec.radiusMeters;
    light.photographed = spec.photographed;
    if (spec.spot) {
      if (!(axis.norm() > 1e-9))
        throw Error(fmt::format("lights.list[{}]: a spot's axis (dir_x, dir_y, dir_z) = ({}, {}, "
                                "{}) has no length",
                                i, spec.direction[0], spec.direction[1], spec.direction[2]),
                    {"lights"});
      axis.normalize();
      light.spot = true;
      light.axis = {axis.x(), axis.y(), axis.z()};
      light.cosHalfAngle = std::cos(spec.halfAngleDeg.valueAt(frame) * M_PI / 180.0);
      light.falloffQ = spec.falloffQ;
    }
    out.push_back(light);
  }
  return out;
}

optics::LocalLight localLight(const FrameLight& light) {
  optics::LocalLight l;
  l.positionMeters = light.positionMeters;
  l.radiusMeters = light.radiusMeters;
  l.spot = light.spot;
  l.axis = light.axis;
  l.cosHalfAngle = light.cosHalfAngle;
  l.q = light.falloffQ;
  return l;
}

double spotFactor(const FrameLight& light, double cosTheta) {
  if (!light.spot) return 1.0;
  if (cosTheta < light.cosHalfAngle) return 0.0;
  const double span = 1.0 - light.cosHalfAngle;
  // A cone of A -> 0: only its axis is lit, at full intensity.
  const double t = span > 1e-12 ? std::min(1.0, (cosTheta - light.cosHalfAngle) / span) : 1.0;
  return (1.0 - light.falloffQ) * t + light.falloffQ;
}

HaloResult addHalos(Image& image, const Camera& camera, const std::vector<FrameLight>& lights,
                    double betaPerMeter, const optics::ScatteringTables& tables,
                    double thresholdRadiance, bool everyPixel) {
  HaloResult result;
  if (lights.empty() || !(betaPerMeter > 0.0)) return result;
  // The lights AOV (--aov lights), when the frame has its planes (the render makes them when
  // asked): the light added, alone; its alpha stays 0 (light adds, it covers nothing). Making
  // four planes of a 1080p frame costs more than ten lights.
  std::array<float*, 3> aov{nullptr, nullptr, nullptr};
  if (image.findPlane("lights.R")) {
    aov = {image.plane("lights.R").data(), image.plane("lights.G").data(),
           image.plane("lights.B").data()};
    image.plane("lights.A");
  }
  const int width = image.width, height = image.height;
  const int tilesX = (width + kTilePx - 1) / kTilePx, tilesY = (height + kTilePx - 1) / kTilePx;
  const int gridW = tilesX + 1, gridH = tilesY + 1;
  const std::vector<float>* depth = image.findPlane(kDepthPlane);
  auto zAt = [&](int x, int y) {
    return depth ? double((*depth)[static_cast<size_t>(y) * width + x]) : HUGE_VAL;
  };
  auto lengthOf = [](double z, double lengthPerDepth) {
    return std::isfinite(z) && z > 0.0 ? z * lengthPerDepth : HUGE_VAL;
  };
  // The grid: the pixels at every tile's corners (columns 0, 16, ..., the last one), shared by
  // the tiles around them; their rays and the scene's distance along them, once per frame.
  auto gridX = [&](int k) { return std::min(k * kTilePx, width - 1); };
  auto gridY = [&](int k) { return std::min(k * kTilePx, height - 1); };
  const size_t gridCount = static_cast<size_t>(gridW) * gridH;
  std::vector<optics::Vec3> gridRay(gridCount);
  std::vector<double> gridLengthPerDepth(gridCount), gridLength(gridCount);
  for (int gy = 0; gy < gridH; ++gy)
    for (int gx = 0; gx < gridW; ++gx) {
      const size_t g = static_cast<size_t>(gy) * gridW + gx;
      gridRay[g] = unitRay(camera, gridX(gx) + 0.5, gridY(gy) + 0.5, gridLengthPerDepth[g]);
      gridLength[g] = lengthOf(zAt(gridX(gx), gridY(gy)), gridLengthPerDepth[g]);
    }
  auto gridIndex = [&](int tx, int ty, int corner) {
    return static_cast<size_t>(ty + corner / 2) * gridW + (tx + corner % 2);
  };
  // Per tile, once per frame: whether the scene in it is one smooth surface (1/z of a plane is
  // bilinear on the screen: every pixel's within kSmoothDepth of its corners' interpolation; all
  // sky counts too), and the range of its finite depths.
  struct TileDepth {
    bool smooth = true;
    bool sky = false;  // some pixel is sky
    double zMin = HUGE_VAL, zMax = 0.0;
  };
  std::vector<TileDepth> tileDepth(static_cast<size_t>(tilesX) * tilesY);
  tbb::parallel_for(0, tilesX * tilesY, [&](int tile) {
    const int tx = tile % tilesX, ty = tile / tilesX;
    const int x0 = tx * kTilePx, y0 = ty * kTilePx;
    const int x1 = std::min(width, x0 + kTilePx), y1 = std::min(height, y0 + kTilePx);
    const double ex = std::max(1, gridX(tx + 1) - x0), ey = std::max(1, gridY(ty + 1) - y0);
    std::array<double, 4> inverse{};
    for (int c = 0; c < 4; ++c) {
      const double z = zAt(gridX(tx + c % 2), gridY(ty + c / 2));
      inverse[size_t(c)] = std::isfinite(z) && z > 0.0 ? 1.0 / z : 0.0;
    }
    TileDepth& t = tileDepth[static_cast<size_t>(tile)];
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const double z = zAt(x, y);
        const bool finite = std::isfinite(z) && z > 0.0;
        if (finite) t.zMin = std::min(t.zMin, z), t.zMax = std::max(t.zMax, z);
        t.sky = t.sky || !finite;
        const double u = (x - x0) / ex, v = (y - y0) / ey;
        const double plane = (1 - v) * ((1 - u) * inverse[0] + u * inverse[1]) +
                             v * ((1 - u) * inverse[2] + u * inverse[3]);
        const double here = finite ? 1.0 / z : 0.0;
        if (std::abs(here - plane) > kSmoothDepth * std::max(here, plane)) t.smooth = false;
      }
  });
  // What the lights add: per tile, the corner values of the lights interpolated there; per
  // pixel, the lights evaluated there.
  std::vector<std::array<float, 12>> tileCorners(static_cast<size_t>(tilesX) * tilesY);
  // The grid points at a depth edge: their unoccluded glow is needed too.
  std::vector<uint8_t> atEdge(gridCount, 0);
  for (int tile = 0; tile < tilesX * tilesY; ++tile)
    if (!tileDepth[static_cast<size_t>(tile)].smooth)
      for (int c = 0; c < 4; ++c) atEdge[gridIndex(tile % tilesX, tile / tilesX, c)] = 1;
  std::vector<int> gridPx(static_cast<size_t>(gridW)), gridPy(static_cast<size_t>(gridH));
  for (int gx = 0; gx < gridW; ++gx) gridPx[size_t(gx)] = gridX(gx);
  for (int gy = 0; gy < gridH; ++gy) gridPy[size_t(gy)] = gridY(gy);
  std::vector<double> gridInverseDepth(gridCount);
  for (size_t g = 0; g < gridCount; ++g)
    gridInverseDepth[g] =
        std::isfinite(gridLength[g]) ? gridLengthPerDepth[g] / gridLength[g] : 0.0;
  const CornerGrid corners =
      cornerGrid(std::move(gridPx), std::move(gridPy), gridInverseDepth, atEdge);
  std::atomic<size_t> evaluations{0};
  // Pass 1, per light: its glow on the grid (culled when it is invisible everywhere); and all the
  // lights' glow summed there, in each channel.
  struct GridLight {
    const FrameLight* frame;
    optics::LocalLight light;
    std::vector<double> grid, open;
    double px, py;  // its image (-1e9: none)
  };
  std::vector<GridLight> gridLights;
  std::vector<std::array<double, 3>> totalRgb(gridCount, {0.0, 0.0, 0.0});
  const double tileThreshold = thresholdRadiance / double(lights.size());
  for (const FrameLight& frameLight : lights) {
    const optics::LocalLight light = localLight(frameLight);
    const double scale = maxChannel(frameLight.rgbIntensity);
    if (!(scale > 0.0)) {
      ++result.culled;
      continue;
    }
    auto glowAlong = [&](const optics::Vec3& ray, double length) {
      return optics::inscatteredRadiance(tables, light, ray, length, betaPerMeter);
    };
    std::vector<double> grid(gridCount), gridOpen(gridCount);
    // Where the light's image is: its tiles are always evaluated (its peak is between corners).
    double lightPx = -1e9, lightPy = -1e9;
    if (frameLight.positionMeters[2] < 0.0) {
      const double z = -frameLight.positionMeters[2];
      const double px = camera.cx + camera.focalPx * frameLight.positionMeters[0] / z;
      const double py = camera.cy - camera.focalPx * frameLight.positionMeters[1] / z;
      if (std::abs(px) < 1e7 && std::abs(py) < 1e7) lightPx = px, lightPy = py;
    }
    // The glow at the grid's pixels, up to the scene there, coarse to fine; at a depth edge also
    // unoccluded (those points are all evaluated: a cell with one is always split).
    evaluations += glowCoarseToFine(
        corners, lightPx, lightPy, frameLight.spot, everyPixel,
        [&](size_t g) { return glowAlong(gridRay[g], gridLength[g]); }, grid);
    tbb::parallel_for(size_t(0), gridCount, [&](size_t g) {
      gridOpen[g] = !atEdge[g]                     ? 0.0
                    : std::isfinite(gridLength[g]) ? glowAlong(gridRay[g], HUGE_VAL)
                                                   : grid[g];
    });
    // Not even near its own image: the light's glow is invisible here.
    const double brightest = std::max(*std::max_element(grid.begin(), grid.end()),
                                      *std::max_element(gridOpen.begin(), gridOpen.end()));
    if (scale * brightest < thresholdRadiance) {
      ++result.culled;
      continue;
    }
    for (size_t g = 0; g < gridCount; ++g)
      for (size_t k = 0; k < 3; ++k) totalRgb[g][k] += grid[g] * frameLight.rgbIntensity[k];
    gridLights.push_back(
        {&frameLight, light, std::move(grid), std::move(gridOpen), lightPx, lightPy});
  }
  // The least of the channels' sums at each grid point: a light's interpolation error need only
  // be small against all the lights' glow there, not against its own (the far, faint side of
  // one lamp's halo under a hundred others).
  std::vector<double> totalLeast(gridCount);
  for (size_t g = 0; g < gridCount; ++g)
    totalLeast[g] = std::min({totalRgb[g][0], totalRgb[g][1], totalRgb[g][2]});
  // Pass 2, per light: its glow into the tiles.
  for (const GridLight& gridLight : gridLights) {
    const FrameLight& frameLight = *gridLight.frame;
    const optics::LocalLight& light = gridLight.light;
    const double scale = maxChannel(frameLight.rgbIntensity);
    auto glowAlong = [&](const optics::Vec3& ray, double length) {
      return optics::inscatteredRadiance(tables, light, ray, length, betaPerMeter);
    };
    const std::vector<double>& grid = gridLight.grid;
    const std::vector<double>& gridOpen = gridLight.open;
    const double lightPx = gridLight.px, lightPy = gridLight.py;
    // Every pixel within kPeakPx of the bulb's image (a disc of this radius).
    const double peakPx =
        kPeakPx + (frameLight.positionMeters[2] < 0.0
                       ? camera.focalPx * frameLight.radiusMeters / -frameLight.positionMeters[2]
                       : 0.0);
    int lightTileX = -10, lightTileY = -10;
    if (lightPx > -1e8) {
      lightTileX = int(std::floor(lightPx / kTilePx));
      lightTileY = int(std::floor(lightPy / kTilePx));
    }
    tbb::parallel_for(0, tilesX * tilesY, [&](int tile) {
      const int tx = tile % tilesX, ty = tile / tilesX;
      const TileDepth& td = tileDepth[static_cast<size_t>(tile)];
      const bool nearLight = std::abs(tx - lightTileX) <= 1 && std::abs(ty - lightTileY) <= 1;
      // Lit: a corner of this tile or of its 8 neighbours above the threshold shared out among
      // the lights, so that what all the lights leave out of a pixel adds up to under the
      // threshold (many lights each too faint alone still glow together); a beam narrower than a
      // tile passing between all the corners of three tiles in a row would be missed.
      bool lit = nearLight || everyPixel;
      for (int gy = std::max(0, ty - 1); gy <= std::min(tilesY, ty + 2) && !lit; ++gy)
        for (int gx = std::max(0, tx - 1); gx <= std::min(tilesX, tx + 2) && !lit; ++gx)
          lit = scale * grid[static_cast<size_t>(gy) * gridW + gx] >= tileThreshold;
      if (!lit && !td.smooth) {
        // At a depth edge the corners may be hidden while pixels between see past: the
        // unoccluded glow at the corners bounds them.
        for (int c = 0; c < 4 && !lit; ++c)
          lit = scale * gridOpen[gridIndex(tx, ty, c)] >= tileThreshold;
      }
      if (!lit) return;
      const int x0 = tx * kTilePx, y0 = ty * kTilePx;
      const int x1 = std::min(width, x0 + kTilePx), y1 = std::min(height, y0 + kTilePx);
      std::array<double, 4> corner{};
      for (int c = 0; c < 4; ++c) corner[size_t(c)] = grid[gridIndex(tx, ty, c)];
      const auto [lo, hi] = std::minmax_element(corner.begin(), corner.end());
      // The glow turns slowly across the tile against its own least value or all the lights'
      // least glow there, in this light's units: bilinear from its corners.
      double spread = kSmoothGlow * *lo;
      if (!everyPixel) {
        double least = HUGE_VAL;
        for (int c = 0; c < 4; ++c) least = std::min(least, totalLeast[gridIndex(tx, ty, c)]);
        spread = std::max(spread, kSumGlow * least / scale);
      }
      const bool gentle = *hi - *lo <= spread;
      if (!everyPixel && !nearLight && gentle && td.smooth) {
        std::array<float, 12>& sum = tileCorners[static_cast<size_t>(tile)];
        for (int c = 0; c < 4; ++c)
          for (int k = 0; k < 3; ++k)
            sum[size_t(c * 3 + k)] += float(corner[size_t(c)] * frameLight.rgbIntensity[size_t(k)]);
        return;
      }
      std::array<double, 3> rgb = frameLight.rgbIntensity;
      // Into the frame directly: this task alone writes this tile's pixels for this light.
      auto add = [&](int x, int y, double glow) {
        if (!(glow > 0.0)) return;
        const size_t pixel = static_cast<size_t>(y) * width + x;
        for (int k = 0; k < 3; ++k) {
          const float value = float(glow * rgb[size_t(k)]);
          image.rgba[pixel * 4 + size_t(k)] += value;
          if (aov[0]) aov[size_t(k)][pixel] += value;
        }
      };
      // A depth edge: at each corner, the glow for a few ray lengths spanning the tile's depths
      // (kSmoothDepth apart, and the sky's); where, at each length, the corners glow within
      // kSmoothGlow of each other, interpolated in log depth per pixel, then across the corners.
      auto edgeInterpolated = [&]() {
        const int steps =
            td.zMax > td.zMin
                ? std::clamp(int(std::ceil(std::log(td.zMax / td.zMin) / std::log1p(kSmoothDepth))),
                             1, kMaxDepthSteps)
                : 0;
        std::array<std::array<double, kMaxDepthSteps + 2>, 4> byDepth{};
        std::array<double, kMaxDepthSteps + 1> zs{};
        const bool finite = td.zMax > 0.0;
        for (int i = 0; finite && i <= steps; ++i)
          zs[size_t(i)] =
              steps ? td.zMin * std::pow(td.zMax / td.zMin, double(i) / steps) : td.zMin;
        for (int c = 0; c < 4; ++c) {
          const size_t g = gridIndex(tx, ty, c);
          for (int i = 0; finite && i <= steps; ++i)
            byDepth[size_t(c)][size_t(i)] =
                glowAlong(gridRay[g], zs[size_t(i)] * gridLengthPerDepth[g]);
          if (td.sky) byDepth[size_t(c)][kMaxDepthSteps + 1] = gridOpen[g];
        }
        evaluations += size_t(4 * (finite ? steps + 1 : 0));
        for (int i = 0; i <= kMaxDepthSteps + 1; ++i) {
          if (i > steps && i <= kMaxDepthSteps) continue;
          if (i == kMaxDepthSteps + 1 ? !td.sky : !finite) continue;
          double low = HUGE_VAL, high = 0.0;
          for (int c = 0; c < 4; ++c)
            low = std::min(low, byDepth[size_t(c)][size_t(i)]),
            high = std::max(high, byDepth[size_t(c)][size_t(i)]);
          if (!(high <= low * (1.0 + kSmoothGlow))) return false;
        }
        const double ex = std::max(1, gridX(tx + 1) - x0), ey = std::max(1, gridY(ty + 1) - y0);
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) {
            const double z = zAt(x, y);
            std::array<double, 4> at{};
            for (int c = 0; c < 4; ++c) {
              const auto& values = byDepth[size_t(c)];
              if (!(std::isfinite(z) && z > 0.0)) {
                at[size_t(c)] = values[kMaxDepthSteps + 1];
              } else if (steps == 0) {
                at[size_t(c)] = values[0];
              } else {
                const double t =
                    std::clamp(std::log(z / td.zMin) / std::log(td.zMax / td.zMin), 0.0, 1.0) *
                    steps;
                const int i = std::min(int(t), steps - 1);
                at[size_t(c)] =
                    values[size_t(i)] + (t - i) * (values[size_t(i) + 1] - values[size_t(i)]);
              }
            }
            const double u = (x - x0) / ex, v = (y - y0) / ey;
            add(x, y, (1 - v) * ((1 - u) * at[0] + u * at[1]) + v * ((1 - u) * at[2] + u * at[3]));
          }
        return true;
      };
      if (!everyPixel && !nearLight && !td.smooth && edgeInterpolated()) return;
      auto evaluate = [&](int xa, int ya, int xb, int yb) {
        for (int y = ya; y < yb; ++y)
          for (int x = xa; x < xb; ++x) {
            double lengthPerDepth;
            const optics::Vec3 ray = unitRay(camera, x + 0.5, y + 0.5, lengthPerDepth);
            add(x, y, glowAlong(ray, lengthOf(zAt(x, y), lengthPerDepth)));
          }
        evaluations += size_t((xb - xa) * (yb - ya));
      };
      if (everyPixel || !td.smooth) {
        // At depth edges where the glow turns fast: every pixel.
        evaluate(x0, y0, x1, y1);
        return;
      }
      // One smooth surface, the glow turning fast or the light's image near: the same again on
      // 4 px sub-tiles, their corners evaluated (a 5 x 5 grid, the tile's own corners reused),
      // each interpolated when its corners glow within kSmoothGlow of each other, else (and
      // within kPeakPx of the bulb's image) evaluated at every pixel.
      constexpr int kSub = kTilePx / kSubTilePx;
      std::array<double, (kSub + 1) * (kSub + 1)> sub{};
      std::array<int, kSub + 1> sx{}, sy{};
      for (int i = 0; i <= kSub; ++i) {
        sx[size_t(i)] = std::min(x0 + i * kSubTilePx, gridX(tx + 1));
        sy[size_t(i)] = std::min(y0 + i * kSubTilePx, gridY(ty + 1));
      }
      for (int j = 0; j <= kSub; ++j)
        for (int i = 0; i <= kSub; ++i) {
          double& value = sub[size_t(j * (kSub + 1) + i)];
          if ((i == 0 || i == kSub) && (j == 0 || j == kSub)) {
            value = corner[size_t((j ? 2 : 0) + (i ? 1 : 0))];
            continue;
          }
          double lengthPerDepth;
          const optics::Vec3 ray =
              unitRay(camera, sx[size_t(i)] + 0.5, sy[size_t(j)] + 0.5, lengthPerDepth);
          value = glowAlong(ray, lengthOf(zAt(sx[size_t(i)], sy[size_t(j)]), lengthPerDepth));
        }
      evaluations += size_t((kSub + 1) * (kSub + 1) - 4);
      for (int j = 0; j < kSub; ++j)
        for (int i = 0; i < kSub; ++i) {
          const int xa = x0 + i * kSubTilePx, ya = y0 + j * kSubTilePx;
          const int xb = std::min(x1, xa + kSubTilePx), yb = std::min(y1, ya + kSubTilePx);
          if (xa >= xb || ya >= yb) continue;
          const std::array<double, 4> c{
              sub[size_t(j * (kSub + 1) + i)], sub[size_t(j * (kSub + 1) + i + 1)],
              sub[size_t((j + 1) * (kSub + 1) + i)], sub[size_t((j + 1) * (kSub + 1) + i + 1)]};
          const auto [low, high] = std::minmax_element(c.begin(), c.end());
          const bool peak = nearLight && lightPx >= xa - peakPx && lightPx < xb + peakPx &&
                            lightPy >= ya - peakPx && lightPy < yb + peakPx;
          if (peak || !(*high - *low <= std::max(kSmoothGlow * *low, spread))) {
            evaluate(xa, ya, xb, yb);
            continue;
          }
          const double ex = std::max(1, sx[size_t(i) + 1] - sx[size_t(i)]),
                       ey = std::max(1, sy[size_t(j) + 1] - sy[size_t(j)]);
          for (int y = ya; y < yb; ++y)
            for (int x = xa; x < xb; ++x) {
              const double u = (x - xa) / ex, v = (y - ya) / ey;
              add(x, y, (1 - v) * ((1 - u) * c[0] + u * c[1]) + v * ((1 - u) * c[2] + u * c[3]));
            }
        }
    });
  }
  // Once per frame: the tiles' interpolated corners, into the frame.
  tbb::parallel_for(0, tilesX * tilesY, [&](int tile) {
    const std::array<float, 12>& sum = tileCorners[static_cast<size_t>(tile)];
    if (*std::max_element(sum.begin(), sum.end()) <= 0.0f) return;
    const int tx = tile % tilesX, ty = tile / tilesX;
    const int x0 = tx * kTilePx, y0 = ty * kTilePx;
    const int x1 = std::min(width, x0 + kTilePx), y1 = std::min(height, y0 + kTilePx);
    // Bilinear per row: its two ends from the corners, then steps along it (in float: what is
    // added is float).
    const float ex = float(std::max(1, gridX(tx + 1) - x0)),
                ey = float(std::max(1, gridY(ty + 1) - y0));
    for (int y = y0; y < y1; ++y) {
      const float v = float(y - y0) / ey;
      std::array<float, 3> left{}, step{};
      for (size_t k = 0; k < 3; ++k) {
        left[k] = (1 - v) * sum[k] + v * sum[6 + k];
        step[k] = ((1 - v) * sum[3 + k] + v * sum[9 + k] - left[k]) / ex;
      }
      for (int x = x0; x < x1; ++x) {
        const size_t pixel = static_cast<size_t>(y) * width + x;
        const float u = float(x - x0);
        for (size_t k = 0; k < 3; ++k) {
          const float value = std::max(0.0f, left[k] + u * step[k]);
          image.rgba[pixel * 4 + k] += value;
          if (aov[0]) aov[k][pixel] += value;
        }
      }
    }
  });
  result.pixelsLit = evaluations.load();
  return result;
}

DropLocalLight dropLocalRadiance(const optics::TransferTable& transfer,
                                 const std::vector<FrameLight>& lights, double betaPerMeter,
                                 const std::array<double, 3>& drop,
                                 const std::array<double, 3>& view) {
  std::array<double, 3> sum{0, 0, 0};
  DropLocalLight result;
  double brightest = 0.0;
  for (const FrameLight& light : lights) {
    const std::array<double, 3> w{light.positionMeters[0] - drop[0],
                                  light.positionMeters[1] - drop[1],
                                  light.positionMeters[2] - drop[2]};
    const double distance = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    // Inside the bulb the irradiance stays that of its surface.
    const double d = std::max(distance, light.radiusMeters);
    double cosView = 1.0, cosSpot = 1.0;
    if (distance > 0.0) {
      cosView = (view[0] * w[0] + view[1] * w[1] + view[2] * w[2]) / distance;
      // The spot's theta: between its axis and the light -> drop direction, -w.
      cosSpot = -(light.axis[0] * w[0] + light.axis[1] * w[1] + light.axis[2] * w[2]) / distance;
    }
    const double cone = spotFactor(light, cosSpot);
    if (cone <= 0.0) continue;
    const double irradiancePerIntensity = cone * std::exp(-betaPerMeter * d) / (d * d);
    const double D = transfer.at(std::clamp(cosView, -1.0, 1.0));
    double luminance = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double added = D * irradiancePerIntensity * light.rgbIntensity[size_t(c)];
      sum[size_t(c)] += added;
      luminance += added;
    }
    if (luminance > brightest && distance > 0.0) {
      brightest = luminance;
      result.towardsBrightest = {w[0] / distance, w[1] / distance, w[2] / distance};
    }
  }
  // Float's range bounds it (an intensity of 1e9 at the bulb's surface).
  result.rgb = {float(std::min(sum[0], 1e30)), float(std::min(sum[1], 1e30)),
                float(std::min(sum[2], 1e30))};
  return result;
}

}  // namespace pluvia
