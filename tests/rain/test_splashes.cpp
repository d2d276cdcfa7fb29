// Splashes: the impact rate against the flux integral, impacts only on surfaces facing up and
// drawn only where not occluded, frames independent of the frames before them, and finite
// results at the extremes.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "geometry/camera.h"
#include "image/image.h"
#include "rain/drop_physics.h"
#include "rain/splash_draw.h"
#include "rain/splash_rate.h"
#include "rain/splashes.h"

using namespace pluvia;
using namespace pluvia::rain;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// An independent reference: the trapezoid rule on 200 000 intervals of N(D) v(D).
double fluxReference(SizeDistribution d, VelocityModel v, double rate, double lo, double hi) {
  const int n = 200000;
  const double h = (hi - lo) / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double x = lo + i * h;
    sum += (i == 0 || i == n ? 0.5 : 1.0) * sizeDensityPerMm(d, rate, x) * terminalVelocity(v, x);
  }
  return sum * h;
}

// z-depth of the ground y = 0 seen by `camera` at each pixel (+inf above the horizon).
std::vector<float> groundDepth(const Camera& camera) {
  std::vector<float> depth(size_t(camera.width) * size_t(camera.height));
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
      const double t = ray.y() < 0.0 ? -camera.positionMeters.y() / ray.y() : kInf;
      depth[size_t(y) * size_t(camera.width) + size_t(x)] = float(t);  // ray has z = -1
    }
  return depth;
}

}  // namespace

TEST(SplashRate, ClosedFormAndSimpsonMatchTheFluxIntegral) {
  for (double rate : {0.1, 15.0, 500.0}) {
    for (auto d : {SizeDistribution::MarshallPalmer, SizeDistribution::Gamma})
      for (auto v : {VelocityModel::Atlas, VelocityModel::GunnKinzer}) {
        const double f = impactsPerSquareMeterSecond(d, v, rate, 0.5, 6.0);
        EXPECT_NEAR(f, fluxReference(d, v, rate, 0.5, 6.0), 1e-4 * f) << rate;
      }
    // Below 0.109 mm Atlas's fit goes negative: the flux counts those drops as not falling.
    const double all = impactsPerSquareMeterSecond(SizeDistribution::MarshallPalmer,
                                                   VelocityModel::Atlas, rate, 0.0, 6.0);
    EXPECT_NEAR(all,
                fluxReference(SizeDistribution::MarshallPalmer, VelocityModel::Atlas, rate,
                              std::log(10.3 / 9.65) / 0.6, 6.0),
                1e-4 * all);
  }
  EXPECT_EQ(impactsPerSquareMeterSecond(SizeDistribution::MarshallPalmer, VelocityModel::Atlas, 0.0,
                                        0.5, 6.0),
            0.0);
}

TEST(SplashRate, ImpactDiametersFollowTheFlux) {
  // The mean landing diameter from samples against the flux-weighted mean by quadrature.
  const double rate = 15.0;
  const ImpactDiameters sampler(SizeDistribution::MarshallPalmer, VelocityModel::Atlas, rate, 0.5,
                                6.0);
  double sampled = 0.0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) sampled += sampler.sampleMm((i + 0.5) / n);
  sampled /= n;
  double num = 0.0, den = 0.0;
  for (double x = 0.5; x < 6.0; x += 1e-4) {
    const double w = sizeDensityPerMm(SizeDistribution::MarshallPalmer, rate, x) *
                     terminalVelocity(VelocityModel::Atlas, x);
    num += w * x, den += w;
  }
  EXPECT_NEAR(sampled, num / den, 0.005 * num / den);
}

TEST(Splashes, ImpactCountMatchesTheFluxOverTheGround) {
  // Looking straight down from 3 m: the ground in view is exactly (w * 3 / f) x (h * 3 / f).
  const Camera camera = Camera::fromFieldOfView(160, 120, 60.0, 90.0, 3.0);
  const std::vector<float> depth = groundDepth(camera);
  const double area =
      (camera.width * 3.0 / camera.focalPx) * (camera.height * 3.0 / camera.focalPx);
  const std::vector<float> perPixel = upFacingAreaPerPixel(camera, depth, 30.0);
  double summed = 0.0;
  for (float a : perPixel) summed += a;
  EXPECT_NEAR(summed, area, 0.01 * area);
  const double rate = 15.0, fps = 24.0;
  const double flux = impactsPerSquareMeterSecond(SizeDistribution::MarshallPalmer,
                                                  VelocityModel::Atlas, rate, 0.5, 6.0);
  const SplashField field{depth, perPixel, flux};
  const ImpactDiameters diameters(SizeDistribution::MarshallPalmer, VelocityModel::Atlas, rate, 0.5,
                                  6.0);
  const int frames = 400;
  size_t count = 0;
  for (int f = 0; f < frames; ++f)
    count += impactsBorn(field, camera, f, fps, 7, diameters, VelocityModel::Atlas).size();
  const double expected = flux * area * frames / fps;
  ASSERT_GT(expected, 2000.0);  // so that 5 % is more than 2 sigma of Poisson noise
  EXPECT_NEAR(double(count), expected, 0.05 * expected);
}

TEST(Splashes, OnlySurfacesFacingUpTakeImpacts) {
  // Looking level at a wall 5 m away: nothing faces up.
  const Camera level = Camera::fromFieldOfView(64, 48, 60.0, 0.0, 1.6);
  const std::vector<float> wall(size_t(64 * 48), 5.0f);
  for (float a : upFacingAreaPerPixel(level, wall, 30.0)) ASSERT_EQ(a, 0.0f);
  // A slope of 45 deg (seen from a camera tilted 45 deg down, a constant z-depth plane is
  // tilted 45 deg) faces up too little for 30 deg, enough for 50 deg.
  const Camera tilted = Camera::fromFieldOfView(64, 48, 40.0, 45.0, 1.6);
  for (float a : upFacingAreaPerPixel(tilted, wall, 30.0)) ASSERT_EQ(a, 0.0f);
  double some = 0.0;
  for (float a : upFacingAreaPerPixel(tilted, wall, 50.0)) some += a;
  EXPECT_GT(some, 0.0);
  // No ground in view: the sky takes nothing.
  const std::vector<float> sky(size_t(64 * 48), float(kInf));
  for (float a : upFacingAreaPerPixel(level, sky, 30.0)) ASSERT_EQ(a, 0.0f);
}

TEST(Splashes, DrawnOnlyWhereNotOccludedAndFramesIndependent) {
  const Camera camera = Camera::fromFieldOfView(200, 150, 50.0, 40.0, 1.6);
  std::vector<float> depth = groundDepth(camera);
  const std::vector<float> ground = depth;
  // A post 1 m away over the middle columns hides the ground behind it.
  for (int y = 0; y < camera.height; ++y)
    for (int x = 90; x < 110; ++x) depth[size_t(y) * 200 + size_t(x)] = 1.0f;
  const double rate = 100.0, fps = 24.0;
  const double flux = impactsPerSquareMeterSecond(SizeDistribution::MarshallPalmer,
                                                  VelocityModel::Atlas, rate, 0.5, 6.0);
  const ImpactDiameters diameters(SizeDistribution::MarshallPalmer, VelocityModel::Atlas, rate, 0.5,
                                  6.0);
  auto render = [&](int64_t frame) {
    const SplashField field{depth, upFacingAreaPerPixel(camera, depth, 30.0), flux};
    std::vector<ShadedParticle> particles;
    for (int64_t b = frame - 10; b <= frame; ++b)
      for (const Impact& i : impactsBorn(field, camera, b, fps, 3, diameters, VelocityModel::Atlas))
        for (const SplashParticle& p : splashParticles(i, frame / fps, frame / fps + 0.02))
          particles.push_back({p, {1.0f, 1.0f, 1.0f}});
    Image image(camera.width, camera.height);
    std::vector<float> alpha(image.pixelCount(), 0.0f);
    drawSplashParticles(image, alpha, depth, camera, particles, 1.0f);
    return alpha;
  };
  render(4);  // frames rendered before do not change frame 5
  const std::vector<float> a = render(5), b = render(5);
  EXPECT_EQ(a, b);
  double onGround = 0.0, onPost = 0.0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const float v = a[size_t(y) * 200 + size_t(x)];
      ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
      (x >= 90 && x < 110 ? onPost : onGround) += v;
    }
  EXPECT_GT(onGround, 1.0);
  EXPECT_EQ(onPost, 0.0);  // the post faces the camera and stands in front of every splash
}

TEST(Splashes, FiniteAtTheExtremes) {
  const Camera camera = Camera::fromFieldOfView(80, 60, 60.0, 30.0, 1.6);
  const std::vector<float> depth = groundDepth(camera);
  for (double rate : {0.1, 500.0}) {
    const double flux = impactsPerSquareMeterSecond(SizeDistribution::MarshallPalmer,
                                                    VelocityModel::Atlas, rate, 0.5, 6.0);
    const ImpactDiameters diameters(SizeDistribution::MarshallPalmer, VelocityModel::Atlas, rate,
                                    0.5, 6.0);
    const SplashField field{depth, upFacingAreaPerPixel(camera, depth, 30.0), flux};
    for (const Impact& i :
         impactsBorn(field, camera, 0, 24.0, 1, diameters, VelocityModel::Atlas)) {
      ASSERT_TRUE(i.point.allFinite());
      // On the ground: 1 / z is affine in the image over a plane, and interpolated so.
      EXPECT_NEAR(i.point.y(), 0.0, 1e-5);
      for (const SplashParticle& p : splashParticles(i, 0.0, 0.05))
        ASSERT_TRUE(p.from.allFinite() && p.to.allFinite());
    }
  }
}

TEST(Splashes, ThinningKeepsTheExpectedCoverageOfFaintParticles) {
  // One still particle at every pixel centre, each covering its own pixel alone (a sub-pixel
  // particle's rim reaches no neighbour's centre) by opacity * d_px^2 = 1/512: half the thinned
  // level, so about half are drawn, at 1/256 each. The coverage summed over the frame is a
  // binomial count: 30 000 particles, sd 0.6 % of the total; tolerance 3 %.
  const Camera camera = Camera::fromFieldOfView(200, 150, 50.0, 0.0, 1.6);
  const double z = 10.0, coverage = 1.0 / 512.0;
  std::vector<ShadedParticle> particles;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const Eigen::Vector3d p =
          camera.positionMeters + camera.worldFromCamera * (camera.rayCamera(x + 0.5, y + 0.5) * z);
      particles.push_back({{p, p, std::sqrt(coverage) * z / camera.focalPx}, {1.0f, 1.0f, 1.0f}});
    }
  Image image(camera.width, camera.height);
  std::vector<float> alpha(image.pixelCount(), 0.0f);
  const std::vector<float> depth(image.pixelCount(), float(kInf));
  drawSplashParticles(image, alpha, depth, camera, particles, 1.0f);
  double sum = 0.0;
  size_t drawn = 0;
  for (float a : alpha) {
    ASSERT_TRUE(a == 0.0f || std::abs(a - kThinnedCoverage) < 1e-6f) << a;
    sum += a, drawn += a > 0.0f;
  }
  EXPECT_NEAR(sum, coverage * double(particles.size()), 0.03 * coverage * double(particles.size()));
  EXPECT_GT(drawn, particles.size() * 4 / 10);
  EXPECT_LT(drawn, particles.size() * 6 / 10);
}

TEST(CrownSheet, TheFarWallMirrorsTheSkyAndTheNearWallTheGround) {
  // A camera level with a crown looks along -Z; the far wall (outward -Z) turns its inner face to
  // the camera, whose normal leans up by kCrownLeanDeg: the mirror direction rises at twice it.
  const double lean = kCrownLeanDeg * M_PI / 180.0;
  const Eigen::Vector3d towardsCamera(0, 0, 1);
  const SheetReflection far = crownSheetReflection(Eigen::Vector3d(0, 0, -1), towardsCamera);
  EXPECT_NEAR(far.mirrorDirection.y(), std::sin(2 * lean), 1e-12);
  EXPECT_NEAR(far.mirrorDirection.z(), std::cos(2 * lean), 1e-12);
  const SheetReflection near = crownSheetReflection(Eigen::Vector3d(0, 0, 1), towardsCamera);
  EXPECT_NEAR(near.mirrorDirection.y(), -std::sin(2 * lean), 1e-12);
  // Both at incidence lean: a thin film's 2 R / (1 + R) of Fresnel's R for water there (an
  // independent evaluation of the s and p reflectances).
  const double n = 1.333, ci = std::cos(lean), st = std::sin(lean) / n;
  const double ct = std::sqrt(1 - st * st);
  const double rs = std::pow((ci - n * ct) / (ci + n * ct), 2);
  const double rp = std::pow((ct - n * ci) / (ct + n * ci), 2);
  const double r = 0.5 * (rs + rp);
  EXPECT_NEAR(far.reflectance, 2 * r / (1 + r), 1e-9);
  EXPECT_NEAR(near.reflectance, far.reflectance, 1e-12);
  // A side patch seen edge-on reflects almost everything, at normal incidence about 4 %.
  const SheetReflection side = crownSheetReflection(Eigen::Vector3d(1, 0, 0), towardsCamera);
  EXPECT_GT(side.reflectance, 0.95);
  const Eigen::Vector3d down(0, -std::sin(lean), std::cos(lean));  // the near face's own normal
  const SheetReflection normal = crownSheetReflection(Eigen::Vector3d(0, 0, 1), down);
  EXPECT_NEAR(normal.reflectance, 2 * 0.02037 / 1.02037, 1e-4);
  EXPECT_NEAR(normal.mirrorDirection.dot(down), 1.0, 1e-12);
}

TEST(CrownSheet, PatchesShareTheAreaTheCameraSeesAndFaceOutwards) {
  // Two walls 2 r wide and D tall, r at the middle of the exposure: 4 r D over the patches.
  Impact impact;
  impact.point = Eigen::Vector3d(0, 0, -3);
  impact.diameterMm = 2.0;
  impact.speedMetersPerSecond = 6.5;
  impact.timeSeconds = 0.0;
  const double life = 20.0 * 2e-3 / 6.5;
  const std::vector<SplashParticle> particles = splashParticles(impact, 0.0, life, 0.0);
  double area = 0.0;
  int patches = 0;
  for (const SplashParticle& p : particles) {
    if (p.crownOutward.squaredNorm() == 0.0) continue;
    ++patches;
    area += M_PI / 4 * p.diameterMeters * p.diameterMeters;
    // Outward: the patch moves along its own direction, on the horizontal.
    const Eigen::Vector3d moved = p.to - p.from;
    EXPECT_NEAR(moved.normalized().dot(p.crownOutward), 1.0, 1e-9);
    EXPECT_NEAR(p.crownOutward.y(), 0.0, 1e-12);
  }
  EXPECT_EQ(patches, kCrownPoints);
  const double rMiddle = 0.5 * (0.0 + 2.0 * 2e-3);
  EXPECT_NEAR(area, 4.0 * rMiddle * 2e-3, 1e-12);
  // Narrower than a pixel: one particle with all of that area, marked as the merged crown.
  const std::vector<SplashParticle> merged = splashParticles(impact, 0.0, life, 1.0);
  ASSERT_FALSE(merged.empty());
  EXPECT_TRUE(merged.front().crownMerged);
  EXPECT_NEAR(M_PI / 4 * merged.front().diameterMeters * merged.front().diameterMeters, area,
              1e-12);
}
