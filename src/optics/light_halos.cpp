#include "optics/light_halos.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "util/parallel.h"

namespace pluvia::optics {
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

Vec3 unitRay(const Camera& camera, double px, double py, double& lengthPerDepth) {
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
    forEachIndex(todo.size(), [&](size_t k) { glow[todo[k]] = evaluate(todo[k]); });
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

// The frame as the halos see it, once per frame: its 16 px tiles, the grid of their corner
// pixels (columns 0, 16, ..., the last one; shared by the tiles around them) with their rays and
// the scene's distance along them, and per tile its depths.
struct HaloFrame {
  // Per tile: whether the scene in it is one smooth surface (1/z of a plane is bilinear on the
  // screen: every pixel's within kSmoothDepth of its corners' interpolation; all sky counts too),
  // and the range of its finite depths.
  struct TileDepth {
    bool smooth = true;
    bool sky = false;  // some pixel is sky
    double zMin = HUGE_VAL, zMax = 0.0;
  };

  explicit HaloFrame(const Camera& camera) : camera(camera) {}

  const Camera& camera;
  int width = 0, height = 0, tilesX = 0, tilesY = 0, gridW = 0, gridH = 0;
  const std::vector<float>* depth = nullptr;
  std::vector<Vec3> gridRay;
  std::vector<double> gridLengthPerDepth, gridLength;
  std::vector<TileDepth> tileDepth;
  std::vector<uint8_t> atEdge;  // the grid points at a depth edge: their unoccluded glow is needed
  CornerGrid corners;

  size_t gridCount() const { return static_cast<size_t>(gridW) * gridH; }
  int tileCount() const { return tilesX * tilesY; }
  int gridX(int k) const { return std::min(k * kTilePx, width - 1); }
  int gridY(int k) const { return std::min(k * kTilePx, height - 1); }
  size_t gridIndex(int tx, int ty, int corner) const {
    return static_cast<size_t>(ty + corner / 2) * gridW + (tx + corner % 2);
  }
  double zAt(int x, int y) const {
    return depth ? double((*depth)[static_cast<size_t>(y) * width + x]) : HUGE_VAL;
  }
  static double lengthOf(double z, double lengthPerDepth) {
    return std::isfinite(z) && z > 0.0 ? z * lengthPerDepth : HUGE_VAL;
  }
};

void measureTileDepths(HaloFrame& frame) {
  frame.tileDepth.assign(static_cast<size_t>(frame.tileCount()), {});
  forEachIndex(frame.tileCount(), [&](int tile) {
    const int tx = tile % frame.tilesX, ty = tile / frame.tilesX;
    const int x0 = tx * kTilePx, y0 = ty * kTilePx;
    const int x1 = std::min(frame.width, x0 + kTilePx), y1 = std::min(frame.height, y0 + kTilePx);
    const double ex = std::max(1, frame.gridX(tx + 1) - x0),
                 ey = std::max(1, frame.gridY(ty + 1) - y0);
    std::array<double, 4> inverse{};
    for (int c = 0; c < 4; ++c) {
      const double z = frame.zAt(frame.gridX(tx + c % 2), frame.gridY(ty + c / 2));
      inverse[size_t(c)] = std::isfinite(z) && z > 0.0 ? 1.0 / z : 0.0;
    }
    HaloFrame::TileDepth& t = frame.tileDepth[static_cast<size_t>(tile)];
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const double z = frame.zAt(x, y);
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
}

HaloFrame haloFrame(const Image& image, const Camera& camera) {
  HaloFrame frame(camera);
  frame.width = image.width, frame.height = image.height;
  frame.tilesX = (frame.width + kTilePx - 1) / kTilePx;
  frame.tilesY = (frame.height + kTilePx - 1) / kTilePx;
  frame.gridW = frame.tilesX + 1, frame.gridH = frame.tilesY + 1;
  frame.depth = image.findPlane(kDepthPlane);
  const size_t gridCount = frame.gridCount();
  frame.gridRay.resize(gridCount);
  frame.gridLengthPerDepth.resize(gridCount), frame.gridLength.resize(gridCount);
  for (int gy = 0; gy < frame.gridH; ++gy)
    for (int gx = 0; gx < frame.gridW; ++gx) {
      const size_t g = static_cast<size_t>(gy) * frame.gridW + gx;
      frame.gridRay[g] = unitRay(camera, frame.gridX(gx) + 0.5, frame.gridY(gy) + 0.5,
                                 frame.gridLengthPerDepth[g]);
      frame.gridLength[g] = HaloFrame::lengthOf(frame.zAt(frame.gridX(gx), frame.gridY(gy)),
                                                frame.gridLengthPerDepth[g]);
    }
  measureTileDepths(frame);
  frame.atEdge.assign(gridCount, 0);
  for (int tile = 0; tile < frame.tileCount(); ++tile)
    if (!frame.tileDepth[static_cast<size_t>(tile)].smooth)
      for (int c = 0; c < 4; ++c)
        frame.atEdge[frame.gridIndex(tile % frame.tilesX, tile / frame.tilesX, c)] = 1;
  std::vector<int> gridPx(static_cast<size_t>(frame.gridW)),
      gridPy(static_cast<size_t>(frame.gridH));
  for (int gx = 0; gx < frame.gridW; ++gx) gridPx[size_t(gx)] = frame.gridX(gx);
  for (int gy = 0; gy < frame.gridH; ++gy) gridPy[size_t(gy)] = frame.gridY(gy);
  std::vector<double> gridInverseDepth(gridCount);
  for (size_t g = 0; g < gridCount; ++g)
    gridInverseDepth[g] = std::isfinite(frame.gridLength[g])
                              ? frame.gridLengthPerDepth[g] / frame.gridLength[g]
                              : 0.0;
  frame.corners = cornerGrid(std::move(gridPx), std::move(gridPy), gridInverseDepth, frame.atEdge);
  return frame;
}

// One light's glow on the grid: up to the scene (`grid`) and, at depth edges, unoccluded
// (`open`); and where its image is (-1e9: none).
struct GridLight {
  const LocalLight* light;
  std::vector<double> grid, open;
  double px, py;
};

// Pass 1, per light: its glow on the grid (culled when it is invisible everywhere). Adds all the
// kept lights' glow there, per channel, into `totalRgb`.
std::vector<GridLight> glowOnGrid(const HaloFrame& frame, const std::vector<LocalLight>& lights,
                                  double betaPerMeter, const ScatteringTables& tables,
                                  double thresholdRadiance, bool everyPixel, HaloResult& result,
                                  std::atomic<size_t>& evaluations,
                                  std::vector<std::array<double, 3>>& totalRgb) {
  const Camera& camera = frame.camera;
  const size_t gridCount = frame.gridCount();
  std::vector<GridLight> gridLights;
  for (const LocalLight& light : lights) {
    const double scale = maxChannel(light.rgbIntensity);
    if (!(scale > 0.0)) {
      ++result.culled;
      continue;
    }
    auto glowAlong = [&](const Vec3& ray, double length) {
      return inscatteredRadiance(tables, light, ray, length, betaPerMeter);
    };
    std::vector<double> grid(gridCount), gridOpen(gridCount);
    // Where the light's image is: its tiles are always evaluated (its peak is between corners).
    double lightPx = -1e9, lightPy = -1e9;
    if (light.positionMeters[2] < 0.0) {
      const double z = -light.positionMeters[2];
      const double px = camera.cx + camera.focalPx * light.positionMeters[0] / z;
      const double py = camera.cy - camera.focalPx * light.positionMeters[1] / z;
      if (std::abs(px) < 1e7 && std::abs(py) < 1e7) lightPx = px, lightPy = py;
    }
    // The glow at the grid's pixels, up to the scene there, coarse to fine; at a depth edge also
    // unoccluded (those points are all evaluated: a cell with one is always split).
    evaluations += glowCoarseToFine(
        frame.corners, lightPx, lightPy, light.spot, everyPixel,
        [&](size_t g) { return glowAlong(frame.gridRay[g], frame.gridLength[g]); }, grid);
    forEachIndex(gridCount, [&](size_t g) {
      gridOpen[g] = !frame.atEdge[g]                     ? 0.0
                    : std::isfinite(frame.gridLength[g]) ? glowAlong(frame.gridRay[g], HUGE_VAL)
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
      for (size_t k = 0; k < 3; ++k) totalRgb[g][k] += grid[g] * light.rgbIntensity[k];
    gridLights.push_back({&light, std::move(grid), std::move(gridOpen), lightPx, lightPy});
  }
  return gridLights;
}

// Where the halos go: the frame and, when asked for, the lights AOV's three planes.
struct HaloTarget {
  Image& image;
  std::array<float*, 3> aov{nullptr, nullptr, nullptr};
};

// Pass 2, one light into the tiles it lights (addHalos' rules): bilinear tiles summed into
// `tileCorners`, the others added to the frame directly (each task alone writes its tile's
// pixels).
class LightIntoTiles {
 public:
  LightIntoTiles(const HaloFrame& frame, const GridLight& gridLight, double betaPerMeter,
                 const ScatteringTables& tables, double tileThreshold,
                 const std::vector<double>& totalLeast, bool everyPixel, HaloTarget& target,
                 std::vector<std::array<float, 12>>& tileCorners, std::atomic<size_t>& evaluations)
      : frame_(frame),
        light_(*gridLight.light),
        grid_(gridLight.grid),
        gridOpen_(gridLight.open),
        lightPx_(gridLight.px),
        lightPy_(gridLight.py),
        betaPerMeter_(betaPerMeter),
        tables_(tables),
        tileThreshold_(tileThreshold),
        totalLeast_(totalLeast),
        everyPixel_(everyPixel),
        target_(target),
        tileCorners_(tileCorners),
        evaluations_(evaluations),
        scale_(maxChannel(light_.rgbIntensity)) {
    // Every pixel within kPeakPx of the bulb's image (a disc of this radius).
    peakPx_ =
        kPeakPx + (light_.positionMeters[2] < 0.0
                       ? frame.camera.focalPx * light_.radiusMeters / -light_.positionMeters[2]
                       : 0.0);
    if (lightPx_ > -1e8) {
      lightTileX_ = int(std::floor(lightPx_ / kTilePx));
      lightTileY_ = int(std::floor(lightPy_ / kTilePx));
    }
  }

  void operator()(int tile) const;

 private:
  struct Tile {
    int tx, ty, x0, y0, x1, y1;
    const HaloFrame::TileDepth& depth;
    bool nearLight;
    std::array<double, 4> corner;
    double spread;
  };

  double glowAlong(const Vec3& ray, double length) const {
    return inscatteredRadiance(tables_, light_, ray, length, betaPerMeter_);
  }
  void add(int x, int y, double glow) const {
    if (!(glow > 0.0)) return;
    const size_t pixel = static_cast<size_t>(y) * frame_.width + x;
    for (int k = 0; k < 3; ++k) {
      const float value = float(glow * light_.rgbIntensity[size_t(k)]);
      target_.image.rgba[pixel * 4 + size_t(k)] += value;
      if (target_.aov[0]) target_.aov[size_t(k)][pixel] += value;
    }
  }
  bool lit(int tx, int ty, bool nearLight, bool smooth) const;
  bool edgeInterpolated(const Tile& t) const;
  void evaluate(int xa, int ya, int xb, int yb) const;
  void subTiles(const Tile& t) const;

  const HaloFrame& frame_;
  const LocalLight& light_;
  const std::vector<double>& grid_;
  const std::vector<double>& gridOpen_;
  double lightPx_, lightPy_;
  double betaPerMeter_;
  const ScatteringTables& tables_;
  double tileThreshold_;
  const std::vector<double>& totalLeast_;
  bool everyPixel_;
  HaloTarget& target_;
  std::vector<std::array<float, 12>>& tileCorners_;
  std::atomic<size_t>& evaluations_;
  double scale_;
  double peakPx_ = 0.0;
  int lightTileX_ = -10, lightTileY_ = -10;
};

// Lit: a corner of this tile or of its 8 neighbours above the threshold shared out among the
// lights, so that what all the lights leave out of a pixel adds up to under the threshold (many
// lights each too faint alone still glow together); a beam narrower than a tile passing between
// all the corners of three tiles in a row would be missed.
bool LightIntoTiles::lit(int tx, int ty, bool nearLight, bool smooth) const {
  bool lit = nearLight || everyPixel_;
  for (int gy = std::max(0, ty - 1); gy <= std::min(frame_.tilesY, ty + 2) && !lit; ++gy)
    for (int gx = std::max(0, tx - 1); gx <= std::min(frame_.tilesX, tx + 2) && !lit; ++gx)
      lit = scale_ * grid_[static_cast<size_t>(gy) * frame_.gridW + gx] >= tileThreshold_;
  if (!lit && !smooth) {
    // At a depth edge the corners may be hidden while pixels between see past: the unoccluded
    // glow at the corners bounds them.
    for (int c = 0; c < 4 && !lit; ++c)
      lit = scale_ * gridOpen_[frame_.gridIndex(tx, ty, c)] >= tileThreshold_;
  }
  return lit;
}

void LightIntoTiles::operator()(int tile) const {
  const int tx = tile % frame_.tilesX, ty = tile / frame_.tilesX;
  const HaloFrame::TileDepth& td = frame_.tileDepth[static_cast<size_t>(tile)];
  const bool nearLight = std::abs(tx - lightTileX_) <= 1 && std::abs(ty - lightTileY_) <= 1;
  if (!lit(tx, ty, nearLight, td.smooth)) return;
  const int x0 = tx * kTilePx, y0 = ty * kTilePx;
  const int x1 = std::min(frame_.width, x0 + kTilePx), y1 = std::min(frame_.height, y0 + kTilePx);
  std::array<double, 4> corner{};
  for (int c = 0; c < 4; ++c) corner[size_t(c)] = grid_[frame_.gridIndex(tx, ty, c)];
  const auto [lo, hi] = std::minmax_element(corner.begin(), corner.end());
  // The glow turns slowly across the tile against its own least value or all the lights'
  // least glow there, in this light's units: bilinear from its corners.
  double spread = kSmoothGlow * *lo;
  if (!everyPixel_) {
    double least = HUGE_VAL;
    for (int c = 0; c < 4; ++c) least = std::min(least, totalLeast_[frame_.gridIndex(tx, ty, c)]);
    spread = std::max(spread, kSumGlow * least / scale_);
  }
  const bool gentle = *hi - *lo <= spread;
  if (!everyPixel_ && !nearLight && gentle && td.smooth) {
    std::array<float, 12>& sum = tileCorners_[static_cast<size_t>(tile)];
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 3; ++k)
        sum[size_t(c * 3 + k)] += float(corner[size_t(c)] * light_.rgbIntensity[size_t(k)]);
    return;
  }
  const Tile t{tx, ty, x0, y0, x1, y1, td, nearLight, corner, spread};
  if (!everyPixel_ && !nearLight && !td.smooth && edgeInterpolated(t)) return;
  if (everyPixel_ || !td.smooth) {
    // At depth edges where the glow turns fast: every pixel.
    evaluate(x0, y0, x1, y1);
    return;
  }
  subTiles(t);
}

// A depth edge: at each corner, the glow for a few ray lengths spanning the tile's depths
// (kSmoothDepth apart, and the sky's); where, at each length, the corners glow within
// kSmoothGlow of each other, interpolated in log depth per pixel, then across the corners.
// False (nothing added) where they do not.
bool LightIntoTiles::edgeInterpolated(const Tile& t) const {
  const HaloFrame::TileDepth& td = t.depth;
  const int steps =
      td.zMax > td.zMin
          ? std::clamp(int(std::ceil(std::log(td.zMax / td.zMin) / std::log1p(kSmoothDepth))), 1,
                       kMaxDepthSteps)
          : 0;
  std::array<std::array<double, kMaxDepthSteps + 2>, 4> byDepth{};
  std::array<double, kMaxDepthSteps + 1> zs{};
  const bool finite = td.zMax > 0.0;
  for (int i = 0; finite && i <= steps; ++i)
    zs[size_t(i)] = steps ? td.zMin * std::pow(td.zMax / td.zMin, double(i) / steps) : td.zMin;
  for (int c = 0; c < 4; ++c) {
    const size_t g = frame_.gridIndex(t.tx, t.ty, c);
    for (int i = 0; finite && i <= steps; ++i)
      byDepth[size_t(c)][size_t(i)] =
          glowAlong(frame_.gridRay[g], zs[size_t(i)] * frame_.gridLengthPerDepth[g]);
    if (td.sky) byDepth[size_t(c)][kMaxDepthSteps + 1] = gridOpen_[g];
  }
  evaluations_ += size_t(4 * (finite ? steps + 1 : 0));
  for (int i = 0; i <= kMaxDepthSteps + 1; ++i) {
    if (i > steps && i <= kMaxDepthSteps) continue;
    if (i == kMaxDepthSteps + 1 ? !td.sky : !finite) continue;
    double low = HUGE_VAL, high = 0.0;
    for (int c = 0; c < 4; ++c)
      low = std::min(low, byDepth[size_t(c)][size_t(i)]),
      high = std::max(high, byDepth[size_t(c)][size_t(i)]);
    if (!(high <= low * (1.0 + kSmoothGlow))) return false;
  }
  const double ex = std::max(1, frame_.gridX(t.tx + 1) - t.x0),
               ey = std::max(1, frame_.gridY(t.ty + 1) - t.y0);
  for (int y = t.y0; y < t.y1; ++y)
    for (int x = t.x0; x < t.x1; ++x) {
      const double z = frame_.zAt(x, y);
      std::array<double, 4> at{};
      for (int c = 0; c < 4; ++c) {
        const auto& values = byDepth[size_t(c)];
        if (!(std::isfinite(z) && z > 0.0)) {
          at[size_t(c)] = values[kMaxDepthSteps + 1];
        } else if (steps == 0) {
          at[size_t(c)] = values[0];
        } else {
          const double s =
              std::clamp(std::log(z / td.zMin) / std::log(td.zMax / td.zMin), 0.0, 1.0) * steps;
          const int i = std::min(int(s), steps - 1);
          at[size_t(c)] = values[size_t(i)] + (s - i) * (values[size_t(i) + 1] - values[size_t(i)]);
        }
      }
      const double u = (x - t.x0) / ex, v = (y - t.y0) / ey;
      add(x, y, (1 - v) * ((1 - u) * at[0] + u * at[1]) + v * ((1 - u) * at[2] + u * at[3]));
    }
  return true;
}

// Every pixel of [xa, xb) x [ya, yb) evaluated.
void LightIntoTiles::evaluate(int xa, int ya, int xb, int yb) const {
  for (int y = ya; y < yb; ++y)
    for (int x = xa; x < xb; ++x) {
      double lengthPerDepth;
      const Vec3 ray = unitRay(frame_.camera, x + 0.5, y + 0.5, lengthPerDepth);
      add(x, y, glowAlong(ray, HaloFrame::lengthOf(frame_.zAt(x, y), lengthPerDepth)));
    }
  evaluations_ += size_t((xb - xa) * (yb - ya));
}

// One smooth surface, the glow turning fast or the light's image near: the tile's rule again on
// 4 px sub-tiles, their corners evaluated (a 5 x 5 grid, the tile's own corners reused), each
// interpolated when its corners glow within kSmoothGlow of each other, else (and within kPeakPx
// of the bulb's image) evaluated at every pixel.
void LightIntoTiles::subTiles(const Tile& t) const {
  constexpr int kSub = kTilePx / kSubTilePx;
  std::array<double, (kSub + 1) * (kSub + 1)> sub{};
  std::array<int, kSub + 1> sx{}, sy{};
  for (int i = 0; i <= kSub; ++i) {
    sx[size_t(i)] = std::min(t.x0 + i * kSubTilePx, frame_.gridX(t.tx + 1));
    sy[size_t(i)] = std::min(t.y0 + i * kSubTilePx, frame_.gridY(t.ty + 1));
  }
  for (int j = 0; j <= kSub; ++j)
    for (int i = 0; i <= kSub; ++i) {
      double& value = sub[size_t(j * (kSub + 1) + i)];
      if ((i == 0 || i == kSub) && (j == 0 || j == kSub)) {
        value = t.corner[size_t((j ? 2 : 0) + (i ? 1 : 0))];
        continue;
      }
      double lengthPerDepth;
      const Vec3 ray =
          unitRay(frame_.camera, sx[size_t(i)] + 0.5, sy[size_t(j)] + 0.5, lengthPerDepth);
      value = glowAlong(
          ray, HaloFrame::lengthOf(frame_.zAt(sx[size_t(i)], sy[size_t(j)]), lengthPerDepth));
    }
  evaluations_ += size_t((kSub + 1) * (kSub + 1) - 4);
  for (int j = 0; j < kSub; ++j)
    for (int i = 0; i < kSub; ++i) {
      const int xa = t.x0 + i * kSubTilePx, ya = t.y0 + j * kSubTilePx;
      const int xb = std::min(t.x1, xa + kSubTilePx), yb = std::min(t.y1, ya + kSubTilePx);
      if (xa >= xb || ya >= yb) continue;
      const std::array<double, 4> c{
          sub[size_t(j * (kSub + 1) + i)], sub[size_t(j * (kSub + 1) + i + 1)],
          sub[size_t((j + 1) * (kSub + 1) + i)], sub[size_t((j + 1) * (kSub + 1) + i + 1)]};
      const auto [low, high] = std::minmax_element(c.begin(), c.end());
      const bool peak = t.nearLight && lightPx_ >= xa - peakPx_ && lightPx_ < xb + peakPx_ &&
                        lightPy_ >= ya - peakPx_ && lightPy_ < yb + peakPx_;
      if (peak || !(*high - *low <= std::max(kSmoothGlow * *low, t.spread))) {
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
}

// Once per frame: the tiles' interpolated corners (all the lights' summed), into the frame.
void addTileCorners(const HaloFrame& frame, const std::vector<std::array<float, 12>>& tileCorners,
                    HaloTarget& target) {
  forEachIndex(frame.tileCount(), [&](int tile) {
    const std::array<float, 12>& sum = tileCorners[static_cast<size_t>(tile)];
    if (*std::max_element(sum.begin(), sum.end()) <= 0.0f) return;
    const int tx = tile % frame.tilesX, ty = tile / frame.tilesX;
    const int x0 = tx * kTilePx, y0 = ty * kTilePx;
    const int x1 = std::min(frame.width, x0 + kTilePx), y1 = std::min(frame.height, y0 + kTilePx);
    // Bilinear per row: its two ends from the corners, then steps along it (in float: what is
    // added is float).
    const float ex = float(std::max(1, frame.gridX(tx + 1) - x0)),
                ey = float(std::max(1, frame.gridY(ty + 1) - y0));
    for (int y = y0; y < y1; ++y) {
      const float v = float(y - y0) / ey;
      std::array<float, 3> left{}, step{};
      for (size_t k = 0; k < 3; ++k) {
        left[k] = (1 - v) * sum[k] + v * sum[6 + k];
        step[k] = ((1 - v) * sum[3 + k] + v * sum[9 + k] - left[k]) / ex;
      }
      for (int x = x0; x < x1; ++x) {
        const size_t pixel = static_cast<size_t>(y) * frame.width + x;
        const float u = float(x - x0);
        for (size_t k = 0; k < 3; ++k) {
          const float value = std::max(0.0f, left[k] + u * step[k]);
          target.image.rgba[pixel * 4 + k] += value;
          if (target.aov[0]) target.aov[k][pixel] += value;
        }
      }
    }
  });
}

}  // namespace

HaloResult addHalos(Image& image, const Camera& camera, const std::vector<LocalLight>& lights,
                    double betaPerMeter, const ScatteringTables& tables, double thresholdRadiance,
                    bool everyPixel) {
  HaloResult result;
  if (lights.empty() || !(betaPerMeter > 0.0)) return result;
  // The lights AOV (--aov lights), when the frame has its planes (the render makes them when
  // asked): the light added, alone; its alpha stays 0 (light adds, it covers nothing). Making
  // four planes of a 1080p frame costs more than ten lights.
  HaloTarget target{image};
  if (image.findPlane("lights.R")) {
    target.aov = {image.plane("lights.R").data(), image.plane("lights.G").data(),
                  image.plane("lights.B").data()};
    image.plane("lights.A");
  }
  const HaloFrame frame = haloFrame(image, camera);
  std::atomic<size_t> evaluations{0};
  std::vector<std::array<double, 3>> totalRgb(frame.gridCount(), {0.0, 0.0, 0.0});
  const std::vector<GridLight> gridLights =
      glowOnGrid(frame, lights, betaPerMeter, tables, thresholdRadiance, everyPixel, result,
                 evaluations, totalRgb);
  // The least of the channels' sums at each grid point: a light's interpolation error need only
  // be small against all the lights' glow there, not against its own (the far, faint side of
  // one lamp's halo under a hundred others).
  std::vector<double> totalLeast(frame.gridCount());
  for (size_t g = 0; g < frame.gridCount(); ++g)
    totalLeast[g] = std::min({totalRgb[g][0], totalRgb[g][1], totalRgb[g][2]});
  // What the lights add: per tile, the corner values of the lights interpolated there; per
  // pixel, the lights evaluated there.
  std::vector<std::array<float, 12>> tileCorners(static_cast<size_t>(frame.tileCount()));
  const double tileThreshold = thresholdRadiance / double(lights.size());
  for (const GridLight& gridLight : gridLights)
    forEachIndex(frame.tileCount(),
                 LightIntoTiles(frame, gridLight, betaPerMeter, tables, tileThreshold, totalLeast,
                                everyPixel, target, tileCorners, evaluations));
  addTileCorners(frame, tileCorners, target);
  result.pixelsLit = evaluations.load();
  return result;
}

}  // namespace pluvia::optics
