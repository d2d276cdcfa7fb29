// Ripples: the capillary-gravity dispersion against its closed-form minimum, the ring's radius
// against age at that phase speed, the slope as the derivative of the height profile, and the
// ring's life ending where its slope is under visibility.
#include <cmath>

#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "geometry/camera.h"
#include "image/image.h"
#include "optics/fresnel.h"
#include "rain/ripple_field.h"
#include "rain/ripples.h"

using namespace pluvia::rain;

namespace {

Impact impactOf(double diameterMm) {
  Impact impact;
  impact.diameterMm = diameterMm;
  impact.speedMetersPerSecond = 6.0;
  return impact;
}

// The height profile of rain/ripples.h, written out independently of the slope code.
double height(const RippleRing& ring, double r) {
  const double u = r - ring.radiusMeters, w = ring.packetWidthMeters;
  return ring.amplitudeMeters * std::exp(-u * u / (2 * w * w)) *
         std::cos(ring.wavenumberPerMeter * u);
}

}  // namespace

TEST(Ripples, ThePhaseSpeedsMinimumIsLambsClosedForm) {
  // c_min = (4 g sigma / rho)^(1/4) at k_min = sqrt(rho g / sigma): 0.2313 m/s, 366 rad/m.
  const double kMin = minPhaseSpeedWavenumber();
  EXPECT_NEAR(kMin, std::sqrt(998.0 * 9.81 / 0.0728), 1e-9);
  EXPECT_NEAR(kMin, 366.7, 0.5);
  const double cMin = std::pow(4.0 * 9.81 * 0.0728 / 998.0, 0.25);
  EXPECT_NEAR(capillaryGravityPhaseSpeed(kMin), cMin, 1e-9);
  EXPECT_NEAR(cMin, 0.2313, 5e-4);
  // A minimum: both sides are faster, and there the group speed equals the phase speed.
  EXPECT_GT(capillaryGravityPhaseSpeed(0.8 * kMin), cMin);
  EXPECT_GT(capillaryGravityPhaseSpeed(1.25 * kMin), cMin);
  EXPECT_NEAR(capillaryGravityGroupSpeed(kMin), cMin, 1e-9);
  // Long gravity waves travel at half their phase speed, short capillary ones at 3/2 of it.
  EXPECT_NEAR(capillaryGravityGroupSpeed(1.0) / capillaryGravityPhaseSpeed(1.0), 0.5, 1e-3);
  EXPECT_NEAR(capillaryGravityGroupSpeed(1e5) / capillaryGravityPhaseSpeed(1e5), 1.5, 1e-3);
}

TEST(Ripples, TheRingSpreadsAtTheMinimumPhaseSpeedFromTheCrownsRadius) {
  const Impact impact = impactOf(2.0);
  const double c = capillaryGravityPhaseSpeed(minPhaseSpeedWavenumber());
  EXPECT_NEAR(rippleRing(impact, 0.0).radiusMeters, 0.004, 1e-12);  // the crown's 2 D
  for (double t : {0.05, 0.2, 0.5}) {
    const RippleRing ring = rippleRing(impact, t);
    EXPECT_NEAR(ring.radiusMeters, 0.004 + c * t, 1e-12) << t;
  }
  // Measured as footage would measure it: the outermost crest's radius at two ages.
  auto crest = [&](double t) {
    const RippleRing ring = rippleRing(impact, t);
    double best = 0.0, at = 0.0;
    for (double r = 0.0; r < 0.5; r += 1e-5)
      if (height(ring, r) > best) best = height(ring, r), at = r;
    return at;
  };
  EXPECT_NEAR((crest(0.4) - crest(0.1)) / 0.3, c, 0.01 * c);
}

TEST(Ripples, TheSlopeIsTheHeightsDerivativeAndVanishesAwayFromTheRing) {
  const RippleRing ring = rippleRing(impactOf(3.0), 0.3);
  const double h = 1e-7;
  for (double u = -3.0; u <= 3.0; u += 0.25) {
    const double r = ring.radiusMeters + u * ring.packetWidthMeters;
    const double numeric = (height(ring, r + h) - height(ring, r - h)) / (2 * h);
    EXPECT_NEAR(rippleRadialSlope(ring, r), numeric,
                1e-6 * ring.amplitudeMeters / ring.packetWidthMeters + 1e-9)
        << u;
  }
  EXPECT_EQ(rippleRadialSlope(ring, ring.radiusMeters + 5 * ring.packetWidthMeters), 0.0);
  EXPECT_EQ(rippleRadialSlope(ring, 0.0), 0.0);
}

TEST(Ripples, ALifeEndsWhereTheSlopeFallsUnderVisibilityAndGrowsWithTheDrop) {
  double last = 0.0;
  for (double d : {1.0, 2.0, 4.0}) {
    const Impact impact = impactOf(d);
    const double life = rippleLifeSeconds(impact);
    EXPECT_GT(life, last) << d;
    last = life;
    auto steep = [&](double t) {
      const RippleRing ring = rippleRing(impact, t);
      return ring.amplitudeMeters * ring.wavenumberPerMeter;
    };
    EXPECT_GT(steep(0.99 * life), kMinVisibleSlope) << d;
    EXPECT_LE(steep(1.01 * life), kMinVisibleSlope) << d;
  }
  // A 2 mm drop's ring fades within a second, some 14 cm across: a puddle's ring.
  const double life = rippleLifeSeconds(impactOf(2.0));
  EXPECT_GT(life, 0.3);
  EXPECT_LT(life, 1.0);
  // The film damps at k sqrt(nu omega / 8), over four times the clean surface's 2 nu k^2.
  const double k = minPhaseSpeedWavenumber();
  EXPECT_GT(filmDampingPerSecond(k), 4.0 * 2.0 * kWaterKinematicViscosity * k * k);
  // A drop too small to raise a visible ring has none; none before its impact.
  EXPECT_EQ(rippleLifeSeconds(impactOf(0.02)), 0.0);  // A k = 0.1 D k = 7e-4
  EXPECT_EQ(rippleRing(impactOf(2.0), -0.1).amplitudeMeters, 0.0);
}

namespace {

// A camera 1.6 m above level water (y = 0), looking 40 degrees down, and its depth plane.
struct WaterView {
  pluvia::Camera camera = pluvia::Camera::fromFieldOfView(160, 120, 60.0, 40.0, 1.6);
  std::vector<float> depth;
  WaterView() {
    depth.assign(size_t(camera.width) * size_t(camera.height),
                 std::numeric_limits<float>::infinity());
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
        if (ray.y() >= 0.0) continue;
        const double t = camera.positionMeters.y() / -ray.y();
        depth[size_t(y) * size_t(camera.width) + size_t(x)] = float(t);  // rayCamera's z is -1
      }
  }
  // The world point on the water at pixel (x, y).
  Eigen::Vector3d point(int x, int y) const {
    const double z = depth[size_t(y) * size_t(camera.width) + size_t(x)];
    return camera.positionMeters +
           camera.worldFromCamera * (camera.rayCamera(x + 0.5, y + 0.5) * z);
  }
};

}  // namespace

TEST(RippleField, SlopesOnlyInsideTheWaterAndAlongTheRing) {
  const WaterView view;
  const int w = view.camera.width, h = view.camera.height;
  std::vector<uint8_t> water(size_t(w) * size_t(h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w / 2; ++x) water[size_t(y) * size_t(w) + size_t(x)] = 1;  // left half
  Impact impact = impactOf(3.0);
  impact.point = view.point(w / 2, 3 * h / 4);  // on the water's right edge
  std::vector<float> sx(water.size(), 0.0f), sz(water.size(), 0.0f);
  addRippleSlopes(view.camera, view.depth, water, {&impact}, 0.15, sx, sz);
  const RippleRing ring = rippleRing(impact, 0.15);
  int inside = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const bool sloped = sx[i] != 0.0f || sz[i] != 0.0f;
      if (!water[i]) {
        EXPECT_FALSE(sloped) << x << "," << y;
        continue;
      }
      const Eigen::Vector3d p = view.point(x, y);
      const double r = std::hypot(p.x() - impact.point.x(), p.z() - impact.point.z());
      if (std::abs(r - ring.radiusMeters) > 4.0 * ring.packetWidthMeters) EXPECT_FALSE(sloped);
      if (sloped) {
        ++inside;
        // Radial, and the profile's own slope.
        EXPECT_NEAR(std::hypot(sx[i], sz[i]), std::abs(rippleRadialSlope(ring, r)), 1e-5);
      }
    }
  EXPECT_GT(inside, 20);
}

TEST(RippleField, ATiltedWaterMirrorsTheKnownSkyByFresnel) {
  // A sky of 1 above the horizon and 0 below, and a sky growing with elevation: the pixel's
  // change is R' L(r') - R0 L(r0), computed here by hand for one pixel.
  const WaterView view;
  const int w = view.camera.width, h = view.camera.height;
  const size_t i = size_t(h - 20) * size_t(w) + size_t(w / 2);
  std::vector<float> sx(size_t(w) * size_t(h), 0.0f), sz(sx.size(), 0.0f);
  sz[i] = 0.05f;  // dh/dz: the normal leans towards -z
  pluvia::Image image(w, h);
  for (float& v : image.rgba) v = 0.5f;
  auto sky = [](const Eigen::Vector3d& d) {
    const float l = float(std::max(0.0, d.normalized().y()) * 4.0);
    return std::array<float, 3>{l, l, l};
  };
  shadeRippleMirror(image, view.camera, view.depth, sx, sz, sky);
  const Eigen::Vector3d p = view.point(w / 2, h - 20);
  const Eigen::Vector3d v = (p - view.camera.positionMeters).normalized();
  const Eigen::Vector3d n = Eigen::Vector3d(0.0, 1.0, -0.05).normalized();
  const double c0 = -v.y(), c1 = -v.dot(n);
  const Eigen::Vector3d r0 = v + 2 * c0 * Eigen::Vector3d::UnitY(), r1 = v + 2 * c1 * n;
  // Fresnel at water by hand: unpolarised (Rs + Rp) / 2.
  auto fresnel = [](double ci) {
    const double st = std::sqrt(1 - ci * ci) / 1.333, ct = std::sqrt(1 - st * st);
    const double rs = (ci - 1.333 * ct) / (ci + 1.333 * ct),
                 rp = (ct - 1.333 * ci) / (ct + 1.333 * ci);
    return 0.5 * (rs * rs + rp * rp);
  };
  const double expected = 0.5 + fresnel(c1) * 4.0 * r1.y() - fresnel(c0) * 4.0 * r0.y();
  EXPECT_NEAR(image.rgba[i * 4], expected, 1e-5);
  EXPECT_GT(std::abs(expected - 0.5), 1e-3);  // the tilt shows
  // Untouched pixels keep the plate exactly.
  EXPECT_EQ(image.rgba[(i + 1) * 4], 0.5f);
}

TEST(RippleField, ATiltedWaterMirrorsThePlatesOwnReflectionDisplaced) {
  // The plate's water holds a linear ramp (bilinear sampling reads it exactly); a tilt turns the
  // reflected ray from r0 to r', and the pixel shows what the level water shows where its own
  // reflection is r' (q: the view ray r' mirrored in the level), times R' / R0(q).
  const WaterView view;
  const int w = view.camera.width, h = view.camera.height;
  auto ramp = [](double px, double py) { return 0.1 + 0.001 * (px - 0.5) + 0.002 * (py - 0.5); };
  pluvia::Image image(w, h);
  std::vector<uint8_t> water(size_t(w) * size_t(h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      water[i] = std::isfinite(view.depth[i]);
      for (int c = 0; c < 3; ++c) image.rgba[i * 4 + c] = float(ramp(x + 0.5, y + 0.5));
    }
  const pluvia::Image plate = image;
  const size_t i = size_t(h - 20) * size_t(w) + size_t(w / 2);
  std::vector<float> sx(size_t(w) * size_t(h), 0.0f), sz(sx.size(), 0.0f);
  sx[i] = 0.03f;
  sz[i] = 0.05f;
  auto none = [](const Eigen::Vector3d&) { return std::array<float, 3>{0.0f, 0.0f, 0.0f}; };
  shadeRippleMirror(image, view.camera, view.depth, sx, sz, none, &plate, &water);
  // By hand.
  const Eigen::Vector3d p = view.point(w / 2, h - 20);
  const Eigen::Vector3d v = (p - view.camera.positionMeters).normalized();
  const Eigen::Vector3d n = Eigen::Vector3d(-0.03, 1.0, -0.05).normalized();
  const Eigen::Vector3d r1 = v - 2.0 * v.dot(n) * n;
  double qx, qy, qz;
  ASSERT_TRUE(view.camera.project(
      view.camera.positionMeters + Eigen::Vector3d(r1.x(), -r1.y(), r1.z()), qx, qy, qz));
  EXPECT_GT(std::hypot(qx - (w / 2 + 0.5), qy - (h - 20 + 0.5)), 1.0) << "the ring moves it";
  const double expected = pluvia::optics::fresnelReflectance(-v.dot(n), 1.333) /
                          pluvia::optics::fresnelReflectance(r1.y(), 1.333) * ramp(qx, qy);
  EXPECT_NEAR(image.rgba[i * 4], expected, 1e-5);
  EXPECT_NEAR(image.rgba[i * 4 + 2], expected, 1e-5);
  EXPECT_EQ(image.rgba[(i + 1) * 4], plate.rgba[(i + 1) * 4]) << "untouched pixels keep the plate";
}
