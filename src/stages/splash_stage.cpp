// Splashes: where the rain's drops strike surfaces facing up, a crown and a few droplets
// (rain/splashes.h), with splash.splatter a splatter texture's flash (rain/splatter.h), drawn on
// the CPU over the plate after the rain (rain/splash_draw.h): the droplets shaded like the drops
// (the environment convolved with the drop's transfer function, looked up along each particle's
// view direction), the crown's sheet as the environment it mirrors over what lies behind it
// (rain/splashes.h, crownSheetReflection). Their AOV "splash" (stages/depth_grading.h,
// GradingAov) is what they changed, RGB, and their coverage, A.
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "image/equirect.h"
#include "optics/drop_radiance_map.h"
#include "optics/drop_shading.h"
#include "pipeline/camera_settings.h"
#include "rain/splash_draw.h"
#include "rain/splash_memo.h"
#include "rain/splash_rate.h"
#include "rain/splashes.h"
#include "rain/splatter.h"
#include "stages/cached_drop_radiance.h"
#include "stages/depth_grading.h"
#include "stages/plate_shutter.h"
#include "stages/rain_settings.h"
#include "stages/registry.h"
#include "stages/splash_settings.h"
#include "util/error.h"
#include "util/parallel.h"

namespace pluvia {
namespace {

constexpr double kMaxDiameterMm = 6.0;  // drops break up above (rain/drop_simulation.h)
// A 3 mm drop's crown (rain/splashes.h: radius 2 D): what splash.min_size_px measures.
constexpr double kCrownAcrossMeters = 0.012;
// Impacts made into particles by one task: enough to outweigh the task's cost, few enough that
// two cores share a frame's 10k or so evenly.
constexpr size_t kImpactsPerBlock = 512;
constexpr uint64_t kThinningSalt = 0x7411ed0ULL;  // particle keys apart from the impact's streams

class SplashStage : public Stage {
 public:
  SplashStage(SplashSettings splash, RainSettings rain, CameraSettings camera)
      : splash_(splash), rain_(std::move(rain)), camera_(std::move(camera)) {}

  void prepare(ClipContext& clip) override {
    if (!clip.environment) throw Error("splash needs the lighting stage's environment", {"splash"});
    path_ = clip.cameraPath;
    fps_ = clip.fps;
    resolvePlateShutter(camera_, clip, "splash");
    // A small map is enough: splashes are a few pixels across.
    optics::RadianceMapSettings map;
    map.outputWidth = 64;
    map.inputWidth = 128;
    environment_ = clip.environment->radiance;
    radiance_ = cachedDropRadianceMap(
        clip, clip.environment->radiance,
        optics::channelOptics(optics::kWaterEtaDispersion, optics::kDefaultTerms), map);
  }

  void process(ClipContext&, FrameContext& frame) override {
    const std::vector<float>* depth = frame.image.findPlane(kDepthPlane);
    const double f = double(frame.frame);
    const double rate = rain_.rateMmPerHour.valueAt(f);
    if (!depth || rate <= 0.0) return;
    const Camera camera = path_.cameraAt(f);
    rain::SplashFieldInputs inputs;
    inputs.maxTiltDeg = splash_.maxTiltDeg;
    // Level of detail: beyond this depth a crown is under splash.min_size_px: no splashes there.
    inputs.maxDepthMeters = splash_.minSizePx > 0.0
                                ? camera.focalPx * kCrownAcrossMeters / splash_.minSizePx
                                : std::numeric_limits<double>::infinity();
    inputs.impactsPerSquareMeterSecond = rain::impactsPerSquareMeterSecond(
        rain_.distribution, rain_.velocity, rate, splash_.minDiameterMm, kMaxDiameterMm);
    // A rate whose flux underflows to 0 (1e-308 mm/h) lands no drop: nothing to draw.
    if (!(inputs.impactsPerSquareMeterSecond > 0.0)) return;
    memo_.setField(camera, *depth, inputs);
    const rain::ImpactDiameters diameters(rain_.distribution, rain_.velocity, rate,
                                          splash_.minDiameterMm, kMaxDiameterMm);
    const double open = f / fps_, close = open + camera_.exposureSecondsAt(fps_, f);
    // Splashes born up to the longest life before the shutter opens are still alive.
    const double longest = rain::splashLifeSeconds(
        {{}, 0.0, kMaxDiameterMm, rain::terminalVelocity(rain_.velocity, kMaxDiameterMm), 0});
    const double flash = splash_.splatter ? splash_.splatterMs * 1e-3 : 0.0;
    const int64_t firstBirth = frame.frame - int64_t(std::ceil(std::max(longest, flash) * fps_));
    const std::vector<const std::vector<rain::Impact>*> born =
        memo_.impacts(firstBirth, frame.frame, fps_, rain_.seed, diameters, rate, rain_.velocity);
    // The alive impacts in birth order, cut into fixed blocks made in parallel and drawn in
    // their order: the same picture whatever the thread count.
    std::vector<const rain::Impact*> alive;
    for (const std::vector<rain::Impact>* some : born)
      for (const rain::Impact& impact : *some)
        if (impact.timeSeconds + std::max(rain::splashLifeSeconds(impact), flash) > open)
          alive.push_back(&impact);
    const size_t blocks = (alive.size() + kImpactsPerBlock - 1) / kImpactsPerBlock;
    projected_.resize(blocks);
    std::vector<std::vector<rain::ShadedImpact>> flashes(blocks);
    const float opacity = float(splash_.opacity);
    const double minDropletPx = std::sqrt(double(rain::kMinParticleCoverage) / opacity);
    forEachIndex(blocks, [&](size_t b) {
      std::vector<rain::ProjectedParticle>& out = projected_[b];
      out.clear();  // kept between frames: its memory is reused
      std::vector<rain::SplashParticle> particles;
      for (size_t k = b * kImpactsPerBlock; k < std::min(alive.size(), (b + 1) * kImpactsPerBlock);
           ++k) {
        const rain::Impact& impact = *alive[k];
        const bool flashing = flash > 0.0 && rain::splatterExposureShare(impact.timeSeconds, flash,
                                                                         open, close) > 0.0;
        double px, py, z;
        if (!camera.project(impact.point, px, py, z)) continue;
        // Level of detail per impact: droplets that stay under kMinParticleCoverage even at
        // their nearest to the camera (a sub-pixel particle covers at most opacity * d_px^2)
        // are not made.
        const double nearest = z - rain::dropletReachMeters(impact);
        const bool droplets =
            nearest > 0.0 &&
            camera.focalPx * rain::dropletDiameterMeters(impact) >= minDropletPx * nearest;
        particles.clear();
        rain::appendSplashParticles(impact, open, close, z / camera.focalPx, particles, droplets);
        if (particles.empty() && !flashing) continue;
        // One radiance per splash: its particles lie millimetres apart, the map varies over
        // degrees.
        const Eigen::Vector3d view = (impact.point - camera.positionMeters).normalized();
        const std::array<float, 3> radiance =
            sampleEquirect(radiance_, float(view.x()), float(view.y()), float(view.z()));
        if (flashing) flashes[b].push_back({&impact, radiance});
        const Eigen::Vector3d towardsCamera = -view;
        rain::ProjectedParticle projected;
        for (size_t j = 0; j < particles.size(); ++j) {
          const rain::SplashParticle& particle = particles[j];
          // A droplet: the drop's shading, opaque; a patch of the crown's sheet: what it mirrors,
          // as opaque as the film reflects (what lies behind shows through the rest).
          std::array<float, 3> shade = radiance;
          double share = 1.0;
          if (particle.crownMerged) {
            sheetAverage(towardsCamera, shade, share);
          } else if (particle.crownOutward.squaredNorm() > 0.0) {
            const rain::SheetReflection sheet =
                rain::crownSheetReflection(particle.crownOutward, towardsCamera);
            shade = mirrored(sheet.mirrorDirection);
            share = sheet.reflectance;
          }
          if (rain::projectSplashParticle(camera, particle, float(opacity * share), shade,
                                          impact.key ^ (kThinningSalt + j), projected))
            out.push_back(projected);
        }
      }
    });
    GradingAov aov(frame.image, "splash");
    coverage_.assign(frame.image.pixelCount(), 0.0f);
    // The splatters lie on the surface, under the crowns and droplets.
    std::vector<rain::ShadedImpact> splatters;
    for (auto& some : flashes) splatters.insert(splatters.end(), some.begin(), some.end());
    rain::drawSplatters(frame.image, coverage_, *depth, camera, splatters, flash, open, close,
                        opacity);
    rain::drawProjectedParticles(frame.image, coverage_, *depth, camera.width, camera.height,
                                 projected_);
    aov.finish(frame.image, coverage_);
  }

 private:
  std::array<float, 3> mirrored(const Eigen::Vector3d& direction) const {
    return sampleEquirect(environment_, float(direction.x()), float(direction.y()),
                          float(direction.z()));
  }

  // A crown merged into one particle: its patches' mirrored light, weighted by their
  // reflectances, and their mean reflectance.
  void sheetAverage(const Eigen::Vector3d& towardsCamera, std::array<float, 3>& shade,
                    double& share) const {
    std::array<double, 3> sum{0, 0, 0};
    double reflectance = 0.0;
    for (const Eigen::Vector3d& outward : rain::crownDirections()) {
      const rain::SheetReflection sheet = rain::crownSheetReflection(outward, towardsCamera);
      const std::array<float, 3> light = mirrored(sheet.mirrorDirection);
      for (size_t c = 0; c < 3; ++c) sum[c] += sheet.reflectance * light[c];
      reflectance += sheet.reflectance;
    }
    for (size_t c = 0; c < 3; ++c) shade[c] = float(sum[c] / std::max(reflectance, 1e-12));
    share = reflectance / rain::kCrownPoints;
  }

  SplashSettings splash_;
  RainSettings rain_;
  CameraSettings camera_;
  CameraPath path_;
  double fps_ = 24.0;
  EquirectMap environment_;  // the lighting stage's, for what the crowns mirror
  EquirectMap radiance_;     // the drops' shading, for the droplets
  rain::SplashMemo memo_;
  std::vector<std::vector<rain::ProjectedParticle>> projected_;  // per block of impacts
  std::vector<float> coverage_;  // the frame's splash coverage, kept between frames
};

}  // namespace

StageInfo splashStageInfo() {
  return makeStageInfo(
      splashTable().section(), splashSettings,
      {.noOpReason = [](const SplashSettings& splash, const Preset& p) -> std::string {
         if (!rainSettings(p).falls()) return "no rain falls";
         if (splash.opacity == 0.0) return "opacity is 0";
         return "";
       },
       .reads =
           [](const SplashSettings&, const Preset&) {
             return std::vector<std::string>{"image", "depth", "environment", "camera"};
           },
       .create =
           [](const SplashSettings& splash, const Preset& p) {
             return std::make_unique<SplashStage>(splash, rainSettings(p), cameraSettings(p));
           }});
}

}  // namespace pluvia
