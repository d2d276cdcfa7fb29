// The drop simulation: Mizukami's box with 3-D wrap-around (a steady count), fall and wind
// against closed forms, determinism across chunks, ramps, rain cells, defocus, and extreme
// settings (never NaN, never more drops than the cap).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>

#include <Eigen/Geometry>

#include "rain/drop_simulation.h"
#include "test_support.h"

using namespace pluvia;
using namespace pluvia::rain;

namespace {

Camera baseCamera() {
  return Camera::fromFieldOfView(320, 180, 50, 5, 1.6);
}

CameraAtFrame fixedCamera() {
  const Camera camera = baseCamera();
  return [camera](double) { return camera; };
}

// A camera walking along -Z (forward) at the given speed, 24 frames a second.
CameraAtFrame walkingCamera(double metersPerSecond) {
  const Camera camera = baseCamera();
  return [camera, metersPerSecond](double frame) {
    Camera c = camera;
    c.positionMeters.z() -= metersPerSecond * frame / 24.0;
    return c;
  };
}

RainAt constantRain(double rate, double windSpeed = 0.0, double windDir = 0.0) {
  return [=](double) {
    RainAtFrame r;
    r.rateMmPerHour = rate;
    r.windSpeedMetersPerSecond = windSpeed;
    r.windDirectionDeg = windDir;
    return r;
  };
}

DropSimulationSettings settingsFor(int64_t lastFrame, int64_t maxDrops = 20000) {
  DropSimulationSettings s;
  s.firstFrame = 0;
  s.lastFrame = lastFrame;
  s.maxDrops = maxDrops;
  s.nearMeters = 0.5;
  s.farMeters = 10.0;
  s.stepSeconds = 1.0 / 24.0;
  return s;
}

bool allFinite(const std::vector<rain::StreakInstance>& streaks) {
  for (const auto& s : streaks) {
    const float* f = &s.headX;
    for (int k = 0; k < 11; ++k)
      if (!std::isfinite(f[k])) return false;
  }
  return true;
}

// Largest frame-to-frame change of the drawn streak count, over the mean count.
double worstCountJump(DropSimulation& sim, int frames, const StreakSettings& streak) {
  double previous = -1, worst = 0, sum = 0;
  for (int f = 0; f < frames; ++f) {
    sim.advanceTo(f);
    const double n = double(sim.buildStreaks(streak).size());
    sum += n;
    if (previous >= 0) worst = std::max(worst, std::abs(n - previous));
    previous = n;
  }
  return worst / (sum / frames);
}

TEST(DropSimulation, DropsStayInTheBoxAndTheCountIsSteady) {
  DropSimulation sim(settingsFor(200), fixedCamera(), constantRain(25.0));
  ASSERT_EQ(sim.poolSize(), 20000u);
  const size_t active = sim.activeCount();
  for (int f = 0; f <= 200; f += 5) {
    sim.advanceTo(f);
    EXPECT_EQ(sim.activeCount(), active) << "frame " << f;
    for (size_t i = 0; i < sim.poolSize(); i += 37)
      ASSERT_TRUE(sim.insideBox(sim.positionOf(i))) << "drop " << i << " frame " << f;
  }
  DropSimulation again(settingsFor(200), fixedCamera(), constantRain(25.0));
  // Statistical fluctuation of a few thousand drawn drops crossing the near and far planes
  // (drops in the box's margins are not drawn): about 2 % per frame; at a segment's boundary the
  // two frames' layouts are independent draws (Poisson: sqrt(2) x 2 %), under 12 % at worst over
  // 120 frames (measured 9.6 %); a wrap-around that lost or bunched drops would jump by tens of
  // per cent.
  EXPECT_LT(worstCountJump(again, 120, StreakSettings{}), 0.12);
}

TEST(DropSimulation, CameraFasterThanTheRainKeepsASteadyCount) {
  // 30 m/s forward, five times a drop's fall speed: drops leave by the near face and come back
  // by the far one (the vanishing and generating faces of Mizukami's box).
  DropSimulation sim(settingsFor(200), walkingCamera(30.0), constantRain(25.0));
  StreakSettings streak;
  streak.exposureSeconds = 1.0 / 200.0;
  EXPECT_LT(worstCountJump(sim, 120, streak), 0.08);
  for (size_t i = 0; i < sim.poolSize(); i += 41) EXPECT_TRUE(sim.insideBox(sim.positionOf(i)));
}

TEST(DropSimulation, DropsFallAtTerminalVelocityAndFollowTheWind) {
  DropSimulationSettings s = settingsFor(400, 2000);
  s.wind.gustiness = 0.0;
  s.wind.turbulence = 0.0;
  DropSimulation sim(s, fixedCamera(), constantRain(15.0, 8.0, 0.0));  // 8 m/s toward +X
  sim.advanceTo(300);  // 12.5 s: far beyond every drop's drag time (v_t / g < 1 s)
  std::vector<Eigen::Vector3d> before;
  for (size_t i = 0; i < sim.poolSize(); ++i) before.push_back(sim.positionOf(i));
  sim.advanceTo(301);
  int checked = 0;
  for (size_t i = 0; i < sim.poolSize(); ++i) {
    const Eigen::Vector3d moved = sim.positionOf(i) - before[i];
    if (moved.norm() > 2.0) continue;  // wrapped this step
    ++checked;
    EXPECT_NEAR(moved.x(), 8.0 / 24.0, 1e-3) << i;  // carried at the wind's speed
    EXPECT_NEAR(moved.z(), 0.0, 1e-4) << i;
    // Falling at the terminal velocity of some diameter in [min, max].
    const double fall = -moved.y() * 24.0;
    EXPECT_GE(fall, terminalVelocity(VelocityModel::Atlas, s.minDiameterMm) - 1e-3);
    EXPECT_LE(fall, terminalVelocity(VelocityModel::Atlas, s.maxDiameterMm) + 1e-3);
  }
  EXPECT_GT(checked, 1000);
}

TEST(DropSimulation, FrameNIsTheSameAloneInAChunkOrInAFullRun) {
  DropSimulationSettings s = settingsFor(60, 5000);
  s.wind.turbulence = 0.5;
  s.wind.gustiness = 0.5;
  s.cells.count = 2;
  DropSimulation full(s, walkingCamera(2.0), constantRain(30.0, 6.0, 30.0));
  DropSimulation alone(s, walkingCamera(2.0), constantRain(30.0, 6.0, 30.0));
  for (int f = 0; f <= 40; ++f) full.advanceTo(f);
  alone.advanceTo(40);
  const auto a = full.buildStreaks(StreakSettings{});
  const auto b = alone.buildStreaks(StreakSettings{});
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])), 0);
  // Asked for an earlier frame, the simulation restarts and reproduces it.
  full.advanceTo(10);
  alone.advanceTo(10);
  EXPECT_EQ(full.positionOf(17), alone.positionOf(17));
}

// Any frame number costs the same: a plate numbered from 86400 (timecode 01:00:00:00 at 24 fps)
// simulates its first frame with as many steps as a plate numbered from 0 (no pre-roll), and a
// frame mid-segment with at most 23; the wind, warmed up before each segment, carries its gusts
// across the segments' boundaries.
TEST(DropSimulation, AnyFrameNumberCostsTheSameWork) {
  DropSimulationSettings s = settingsFor(86500, 5000);
  s.wind.turbulence = 0.3;
  s.wind.gustiness = 0.4;
  DropSimulation fromOne(s, fixedCamera(), constantRain(20.0, 3.0, 30.0));
  fromOne.advanceTo(1);
  DropSimulation timecode(s, fixedCamera(), constantRain(20.0, 3.0, 30.0));
  const int64_t constructionWind = timecode.windSteps();
  timecode.advanceTo(86401);
  EXPECT_EQ(fromOne.dropSteps(), 1);
  EXPECT_EQ(timecode.dropSteps(), 1);
  EXPECT_LE(timecode.windSteps() - constructionWind, s.windWarmupFrames + 1);
  DropSimulation late(s, fixedCamera(), constantRain(20.0, 3.0, 30.0));
  late.advanceTo(86423);
  EXPECT_EQ(late.dropSteps(), 23);
  EXPECT_EQ(late.segmentStartOf(86423), 86400);
  EXPECT_EQ(late.segmentStartOf(-5), 0);  // before the first frame: the first frame's drops
  for (size_t i = 0; i < 100; ++i) {
    const Eigen::Vector3d p = late.positionOf(i);
    EXPECT_TRUE(p.allFinite());
    EXPECT_TRUE(late.insideBox(p));
  }
}

// Across a segment's boundary the drops are laid out afresh (a new layout, not the first
// segment's again), and reaching frame 30 through frame 20 or directly gives the same drops.
TEST(DropSimulation, SegmentsAreFreshAndReachedAlikeFromAnyFrame) {
  DropSimulationSettings s = settingsFor(100, 5000);
  s.wind.turbulence = 0.3;
  DropSimulation through(s, fixedCamera(), constantRain(20.0, 3.0, 30.0));
  through.advanceTo(20);
  through.advanceTo(30);
  DropSimulation direct(s, fixedCamera(), constantRain(20.0, 3.0, 30.0));
  direct.advanceTo(30);
  for (size_t i = 0; i < 50; ++i) EXPECT_EQ(through.positionOf(i), direct.positionOf(i));
  DropSimulation first(s, fixedCamera(), constantRain(20.0, 3.0, 30.0));
  DropSimulation second(s, fixedCamera(), constantRain(20.0, 3.0, 30.0));
  second.advanceTo(24);
  int same = 0;
  for (size_t i = 0; i < 200; ++i) same += first.positionOf(i) == second.positionOf(i);
  EXPECT_EQ(same, 0);
}

TEST(DropSimulation, RateRampDrawsMoreDropsAsItRises) {
  DropSimulationSettings s = settingsFor(48, 200000);
  s.farMeters = 4.0;  // a small box: the pool holds the top of the ramp uncapped
  RainAt ramp = [](double frame) {
    RainAtFrame r;
    r.rateMmPerHour = 10.0 * std::clamp(frame / 48.0, 0.0, 1.0);
    return r;
  };
  DropSimulation sim(s, fixedCamera(), ramp);
  ASSERT_LT(sim.poolSize(), 200000u);
  EXPECT_EQ(sim.activeCount(), 0u);
  size_t previous = 0;
  for (int f = 6; f <= 48; f += 6) {
    sim.advanceTo(f);
    EXPECT_GT(sim.activeCount(), previous) << "frame " << f;
    previous = sim.activeCount();
  }
  // At the top of the ramp the pool is drawn at the physical density (it was sized for it).
  const double expected = sim.physicalDensityPerCubicMeter() * sim.boxVolumeCubicMeters();
  EXPECT_NEAR(double(sim.activeCount()), expected, 4.0 * std::sqrt(expected) + 1.0);
}

TEST(DropSimulation, RainCellsAreDenserAtTheirCentre) {
  DropSimulationSettings s = settingsFor(10, 400000);
  s.cells.count = 1;
  s.cells.radiusMeters = 3.0;
  s.cells.peakDensity = 4.0;
  s.cells.regionHalfSizeMeters = 0.0;  // centred on the camera's ground point
  // 1 mm/h: the pool holds the cell's peak density uncapped.
  DropSimulation sim(s, fixedCamera(), constantRain(1.0));
  ASSERT_LT(sim.poolSize(), 400000u);
  // Fraction of the pool drawn near the cell's axis against far from it: the density factor
  // 1 + 3 exp(-r^2 / 2 sigma^2) is about 3.7 on average within 2 m, 1.2 beyond 7 m.
  double nearActive = 0, nearAll = 0, farActive = 0, farAll = 0;
  for (size_t i = 0; i < sim.poolSize(); ++i) {
    const Eigen::Vector3d p = sim.positionOf(i);
    const double r = std::hypot(p.x(), p.z());
    if (r < 2.0) nearAll += 1, nearActive += sim.isActive(i);
    if (r > 7.0) farAll += 1, farActive += sim.isActive(i);
  }
  ASSERT_GT(nearAll, 1000);
  ASSERT_GT(farAll, 1000);
  const double ratio = (nearActive / nearAll) / (farActive / farAll);
  EXPECT_GT(ratio, 2.4);
  EXPECT_LT(ratio, 3.6);
}

TEST(DropSimulation, DefocusWidensStreaksAndKeepsTheirCoverage) {
  DropSimulation sim(settingsFor(10, 20000), fixedCamera(), constantRain(20.0));
  StreakSettings sharp;
  sharp.minWidthPx = 0.0;
  sharp.opacity = 20.0;
  StreakSettings blurred = sharp;
  blurred.focusMeters = 2.0;
  blurred.fNumber = 4.0;
  // The same drops (matched by their head position; faint ones drop out of the blurred set).
  std::map<std::pair<float, float>, rain::StreakInstance> byHead;
  for (const auto& a : sim.buildStreaks(sharp)) byHead[{a.headX, a.headY}] = a;
  int matched = 0, wider = 0, near = 0;
  for (const auto& b : sim.buildStreaks(blurred)) {
    const auto it = byHead.find({b.headX, b.headY});
    ASSERT_NE(it, byHead.end());
    const rain::StreakInstance& a = it->second;
    ++matched;
    EXPECT_GE(b.widthPx, a.widthPx - 1e-4f);
    wider += b.widthPx > 1.5f * a.widthPx;
    // In focus (about 2 m) the width is the pinhole's.
    if (std::abs(a.depthMeters - 2.0f) < 0.02f) {
      ++near;
      EXPECT_NEAR(b.widthPx, a.widthPx, 0.05f * a.widthPx + 1e-3f);
    }
    // Unclamped: alpha over the quad (width x (length + width)), the drop's area, is kept.
    const auto carried = [](const StreakInstance& k) {
      const double length = std::hypot(k.tailX - k.headX, k.tailY - k.headY);
      return double(k.alpha) * k.widthPx * (length + k.widthPx);
    };
    if (a.alpha < 1.0f && b.alpha < 1.0f) {
      EXPECT_NEAR(carried(a), carried(b), 1e-3 * carried(a));
    }
  }
  EXPECT_GT(matched, 200);
  EXPECT_GT(wider, matched / 4);
  EXPECT_GT(near, 0);
}

TEST(DropSimulation, StreakAlphaIsTwoRadiiOverTheDistanceFallen) {
  // Drops falling across the view about 5 m in front of an untilted camera, in still air.
  const Camera camera = Camera::fromFieldOfView(640, 480, 60, 0, 1.6);
  DropSimulationSettings s = settingsFor(0, 20000);
  s.nearMeters = 4.9;
  s.farMeters = 5.1;
  s.boxMarginFraction = 0.0;
  DropSimulation sim(
      s, [camera](double) { return camera; }, constantRain(10.0));
  StreakSettings streak;
  streak.exposureSeconds = 0.01;
  streak.minWidthPx = 0.0;  // no minimum width: alpha is the pure time fraction
  const auto streaks = sim.buildStreaks(streak);
  ASSERT_GT(streaks.size(), 50u);
  for (const auto& st : streaks) {
    const double lengthPx = std::hypot(st.tailX - st.headX, st.tailY - st.headY);
    // Garg and Nayar: alpha = 2r / (v T); on the image, width / length at the same depth, over
    // the quad that is a width longer than the path: width / (length + width).
    EXPECT_NEAR(st.alpha, std::min(1.0, st.widthPx / (lengthPx + st.widthPx)), 1e-5);
    EXPECT_GT(st.tailY, st.headY);  // falling means moving down the image
    // The fall during the exposure, v_t T, seen at the drop's depth.
    const double fallMeters = lengthPx * st.depthMeters / camera.focalPx;
    EXPECT_GE(fallMeters, terminalVelocity(VelocityModel::Atlas, s.minDiameterMm) * 0.01 * 0.98);
    EXPECT_LE(fallMeters, terminalVelocity(VelocityModel::Atlas, s.maxDiameterMm) * 0.01 * 1.02);
  }
}

TEST(DropSimulation, ExtremeSettingsStayFiniteAndBounded) {
  for (double rate : {0.0, 500.0})
    for (double wind : {0.0, 60.0})
      for (double fps : {1.0, 240.0})
        for (double exposure : {1.0 / 8000.0, 1.0}) {
          DropSimulationSettings s = settingsFor(30, 50000);
          s.stepSeconds = 1.0 / fps;
          s.wind.turbulence = 1.0;
          s.wind.gustiness = 1.0;
          DropSimulation sim(s, walkingCamera(rate > 0 ? 50.0 : 0.0),
                             constantRain(rate, wind, 45.0));
          EXPECT_LE(sim.poolSize(), 50000u);
          sim.advanceTo(30);
          StreakSettings streak;
          streak.exposureSeconds = exposure;
          const auto streaks = sim.buildStreaks(streak);
          EXPECT_TRUE(allFinite(streaks)) << rate << " " << wind << " " << fps << " " << exposure;
          if (rate == 0.0) {
            EXPECT_TRUE(streaks.empty());
          }
          for (size_t i = 0; i < sim.poolSize(); i += 101)
            ASSERT_TRUE(sim.positionOf(i).allFinite());
        }
}

TEST(DropSimulation, AThousandFramesKeepMemoryAndTheCountSteady) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's quarantine grows resident memory by design";
#endif
  // Gusts, a stable-fluids field and spread on a camera that walks and turns for 1000 frames:
  // the pool, the box and the wind grid are sized once, so memory must not grow after the
  // first frames, and the drops in the box must stay exactly as many (wrap-around loses
  // none). The streaks drawn do vary: faster (windier) streaks are fainter, and turning
  // changes how the wind crosses the view.
  DropSimulationSettings s = settingsFor(1000);
  s.wind.gustiness = 0.6;
  s.wind.turbulence = 0.6;
  s.spreadMetersPerSecond = 0.5;
  const Camera base = baseCamera();
  CameraAtFrame turning = [base](double frame) {
    Camera c = base;
    c.positionMeters.z() -= 1.5 * frame / 24.0;
    // Yaw 0.05 degrees a frame to the right (about +Y).
    c.worldFromCamera =
        Eigen::AngleAxisd(-0.05 * frame * M_PI / 180.0, Eigen::Vector3d::UnitY()).matrix() *
        base.worldFromCamera;
    return c;
  };
  DropSimulation sim(s, turning, constantRain(25.0, 6.0, 30.0));
  const size_t pool = sim.poolSize(), active = sim.activeCount();
  size_t warm = 0;
  for (int f = 0; f <= 1000; ++f) {
    sim.advanceTo(f);
    const auto streaks = sim.buildStreaks(StreakSettings{});
    if (f == 50) warm = test::residentBytes();
    if (f % 100 == 0) {
      ASSERT_TRUE(allFinite(streaks)) << "frame " << f;
      ASSERT_EQ(sim.activeCount(), active) << "frame " << f;
      for (size_t i = 0; i < sim.poolSize(); i += 97)
        ASSERT_TRUE(sim.insideBox(sim.positionOf(i))) << "drop " << i << " frame " << f;
    }
  }
  EXPECT_EQ(sim.poolSize(), pool);
  EXPECT_LT(test::residentBytes(), warm + 1024 * 1024);
}

}  // namespace

// A stroke whose matte fills a third of its rectangle's width and half its length: each quad
// grows so that the stroke is pi/4 of the drop's drawn width (a swept disc's equivalent width)
// and hypot(path, width) long, about the same centre, keeping alpha x area (the drop's energy).
TEST(DropSimulation, QuadsGrowSoThatTheStrokeIsTheStreak) {
  DropSimulation sim(settingsFor(10, 20000), fixedCamera(), constantRain(20.0));
  StreakSettings plain;
  plain.minWidthPx = 0.0;
  plain.opacity = 3.0;  // no drop falls under the visibility threshold in either set
  StreakSettings fitted = plain;
  fitted.strokeQuadScale = {{3.0f, 2.0f}};
  const auto a = sim.buildStreaks(plain);
  const auto b = sim.buildStreaks(fitted);
  ASSERT_EQ(a.size(), b.size());  // the same drops, in drop order
  ASSERT_GT(a.size(), 100u);
  int checked = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double pathA = std::hypot(a[i].tailX - a[i].headX, a[i].tailY - a[i].headY);
    const double pathB = std::hypot(b[i].tailX - b[i].headX, b[i].tailY - b[i].headY);
    EXPECT_NEAR(b[i].widthPx, 3.0 * 0.25 * M_PI * a[i].widthPx, 1e-4 + 1e-5 * a[i].widthPx);
    const double along =
        std::max(2.0 * std::hypot(pathA, double(a[i].widthPx)), double(b[i].widthPx));
    EXPECT_NEAR(pathB + b[i].widthPx, along, 1e-3 * along + 1e-3);
    EXPECT_NEAR(b[i].headX + b[i].tailX, a[i].headX + a[i].tailX, 1e-2);  // the same centre
    EXPECT_NEAR(b[i].headY + b[i].tailY, a[i].headY + a[i].tailY, 1e-2);
    if (a[i].alpha < 1.0f) {
      ++checked;
      const double carriedA = double(a[i].alpha) * a[i].widthPx * (pathA + a[i].widthPx);
      const double carriedB = double(b[i].alpha) * b[i].widthPx * (pathB + b[i].widthPx);
      EXPECT_NEAR(carriedB, carriedA, 2e-3 * carriedA);
    }
  }
  EXPECT_GT(checked, 50);
}
