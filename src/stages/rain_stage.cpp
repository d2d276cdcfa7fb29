// Rain: particles carrying stroke mattes, drawn on the GPU through headless EGL, shaded by the
// environment (PRT) and composited over the plate (Wang et al. sections 3-4).
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "optics/drop_shading.h"
#include "rain/drop_volume.h"
#include "rain/stroke_library.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia {
namespace {

rain::DropVolumeParams volumeParams(const Preset& p) {
  rain::DropVolumeParams v;
  v.rainRateMmPerHour = p.number("rain.rate_mm_h");
  v.minDiameterMm = p.number("rain.min_diameter_mm");
  v.densityScale = p.number("rain.density_scale");
  v.sizeScale = p.number("rain.size_scale");
  v.nearMeters = p.number("rain.near_m");
  v.farMeters = p.number("rain.far_m");
  v.maxDrops = int64_t(p.number("rain.max_drops"));
  v.seed = uint64_t(p.number("rain.seed"));
  // Wind direction: degrees counter-clockwise from the camera's right seen from above
  // (0 right, 90 away from the camera); the world here is the camera's yaw frame.
  const double speed = p.number("rain.wind.speed_m_s");
  const double dir = p.number("rain.wind.dir_deg") * M_PI / 180.0;
  v.windMetersPerSecond = Eigen::Vector3d(speed * std::cos(dir), 0.0, -speed * std::sin(dir));
  return v;
}

// How the drops are shaded (src/optics/drop_shading.h): "default" looks the drop's radiance up
// in the environment convolved with the drop's transfer function; "paper" is Wang et al.'s 16
// SH coefficients plus c * B.
gpu::ShadingParams dropShading(const Preset& p, const EquirectMap& environment) {
  const std::array<double, 3> eta =
      p.boolean("rain.dispersion")
          ? optics::kWaterEtaDispersion
          : std::array<double, 3>{optics::kWaterEta, optics::kWaterEta, optics::kWaterEta};
  gpu::ShadingParams shading;
  const auto started = std::chrono::steady_clock::now();
  if (p.string("rain.shading") == "default") {
    shading.radianceMap = optics::buildDropRadianceMap(
        environment, optics::channelOptics(eta, optics::kDefaultTerms));
    shading.backgroundWeight = 0.0f;
  } else {
    const optics::PaperShading paper = optics::preparePaperShading(environment, eta);
    shading.shOrder = optics::kPaperShOrder;
    for (const auto& rgb : paper.environmentSh)
      shading.envSh.push_back({float(rgb[0]), float(rgb[1]), float(rgb[2])});
    // The GPU holds one transfer vector: the green channel's (dispersion shows in "default").
    for (int l = 0; l <= optics::kPaperShOrder; ++l) {
      shading.transferZonal.push_back(
          float(optics::zonalRotationFactor(l) * paper.zonal[1][size_t(l)]));
    }
    shading.backgroundWeight = float(p.number("rain.background_weight"));
  }
  log::info(fmt::format("rain: {} drop shading prepared in {:.0f} ms", p.string("rain.shading"),
                        secondsSince(started) * 1000.0));
  return shading;
}

class RainStage : public Stage {
 public:
  explicit RainStage(const Preset& p) : preset_(p) {}

  void prepare(ClipContext& clip) override {
    const Preset& p = preset_;
    if (p.number("rain.min_diameter_mm") >= 6.0)
      throw Error("rain.min_diameter_mm must be below 6 mm", {"rain"});
    volume_ = std::make_unique<rain::DropVolume>(clip.camera, volumeParams(p));
    if (volume_->physicalCount() > double(volume_->drops().size()) + 0.5) {
      log::info(
          fmt::format("rain: {:.0f} drops at this rate in the volume, drawing rain.max_drops = {}",
                      volume_->physicalCount(), volume_->drops().size()));
    }
    atlas_ = loadAtlas(clip);
    streakParams_.exposureSeconds = p.number("camera.exposure_s");
    streakParams_.opacity = p.number("rain.opacity");
    streakParams_.fogDensityPerMeter = p.boolean("fog.enabled") ? p.number("fog.density") : 0.0;
    streakParams_.strokeCount = int(atlas_.rects.size());
    streakParams_.meanMatte = rain::meanMatte(atlas_);
    streakParams_.seed = uint64_t(p.number("rain.seed"));
    if (!clip.environment) throw Error("rain needs the lighting stage's environment", {"rain"});
    // One shading for the clip, or one per key environment of a looming camera.
    if (clip.environment->keys.empty()) shading_ = dropShading(p, clip.environment->radiance);
    for (const auto& [keyFrame, radiance] : clip.environment->keys)
      keyShading_.emplace_back(keyFrame, dropShading(p, radiance));
    renderer_ = std::make_unique<gpu::RainRenderer>(clip.camera.width, clip.camera.height);
    renderer_->setStrokeAtlas(atlas_);
    log::info(fmt::format("rain: {} drops in a {:.1f} x {:.1f} x {:.1f} m box, {} strokes, GPU: {}",
                          volume_->drops().size(), volume_->boxSize().x(), volume_->boxSize().y(),
                          volume_->boxSize().z(), atlas_.rects.size(),
                          renderer_->deviceDescription()));
  }

  void process(ClipContext& clip, FrameContext& frame) override {
    auto streaks = rain::buildStreaks(*volume_, clip.camera, frame.timeSeconds, streakParams_);
    if (keyShading_.empty()) {
      renderer_->render(frame.image, streaks, shading_);
    } else {
      renderer_->render(frame.image, streaks, shadingAt(frame.frame));
    }
  }

 private:
  gpu::StrokeAtlas loadAtlas(ClipContext& clip) const {
    const std::string strokes = preset_.string("rain.strokes");
    if (strokes == "derain") {
      if (!clip.footageStrokes)
        throw Error("rain.strokes is \"derain\" but no strokes were extracted", {"rain"});
      return *clip.footageStrokes;
    }
    // "builtin": the library shipped with pluvia (assets/strokes/builtin.json); else a path.
    const std::string path = strokes == "builtin" ? rain::builtinStrokeLibraryPath() : strokes;
    try {
      return rain::loadStrokeLibrary(path).atlas;
    } catch (const Error& e) {
      throw Error(std::string("rain.strokes: ") + e.what(), {"rain", {}, e.context().file});
    }
  }

  // A looming camera's environment changes over the shot: the shading of the key frames around
  // `frame`, blended linearly (both terms are linear in the environment), the nearest key's
  // beyond the first and last.
  gpu::ShadingParams shadingAt(int64_t frame) const {
    if (frame <= keyShading_.front().first) return keyShading_.front().second;
    if (frame >= keyShading_.back().first) return keyShading_.back().second;
    size_t next = 1;
    while (keyShading_[next].first < frame) ++next;
    const auto& [frameA, a] = keyShading_[next - 1];
    const auto& [frameB, b] = keyShading_[next];
    const float t = float(frame - frameA) / float(frameB - frameA);
    gpu::ShadingParams mixed = a;
    for (size_t i = 0; i < mixed.radianceMap.rgb.size(); ++i)
      mixed.radianceMap.rgb[i] = (1 - t) * a.radianceMap.rgb[i] + t * b.radianceMap.rgb[i];
    for (size_t i = 0; i < mixed.envSh.size(); ++i)
      for (int c = 0; c < 3; ++c)
        mixed.envSh[i][size_t(c)] = (1 - t) * a.envSh[i][size_t(c)] + t * b.envSh[i][size_t(c)];
    return mixed;
  }

  const Preset& preset_;
  std::unique_ptr<rain::DropVolume> volume_;
  gpu::StrokeAtlas atlas_;
  rain::StreakParams streakParams_;
  gpu::ShadingParams shading_;
  std::vector<std::pair<int64_t, gpu::ShadingParams>>
      keyShading_;  // empty: shading_ for every frame
  std::unique_ptr<gpu::RainRenderer> renderer_;
};

}  // namespace

StageInfo rainStageInfo() {
  StageInfo info;
  info.spec.name = "rain";
  info.spec.help =
      "Rain streaks on the GPU (headless EGL): drops by rate, stroke mattes, PRT shading, "
      "composite.";
  info.spec.inputs = {"image", "depth", "environment", "footage_strokes"};
  info.spec.outputs = {"image"};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage"},
      {"rate_mm_h",
       ParamType::Number,
       15.0,
       0.0,
       500.0,
       {},
       "mm/h",
       "rain rate; sets drop count and sizes (Marshall-Palmer)"},
      {"seed", ParamType::Integer, 1, 0, 4294967295.0, {}, "", "random seed; same seed, same rain"},
      {"strokes",
       ParamType::String,
       "builtin",
       {},
       {},
       {},
       "",
       "stroke library: builtin (cut from real rain, shipped), derain (cut from derain.input), or "
       "a LIBRARY.json written by `pluvia strokes`"},
      {"min_diameter_mm",
       ParamType::Number,
       0.8,
       0.05,
       6.0,
       {},
       "mm",
       "smaller drops are left to the fog"},
      {"density_scale",
       ParamType::Number,
       1.0,
       0.0,
       100.0,
       {},
       "",
       "artist scale on the physical drop count"},
      {"size_scale",
       ParamType::Number,
       1.0,
       0.05,
       20.0,
       {},
       "",
       "artist scale on the drawn drop diameter"},
      {"opacity",
       ParamType::Number,
       1.0,
       0.0,
       100.0,
       {},
       "",
       "artist scale on the physical streak alpha"},
      {"near_m", ParamType::Number, 0.5, 0.05, 100.0, {}, "m", "nearest drops drawn"},
      {"far_m", ParamType::Number, 15.0, 0.1, 1000.0, {}, "m", "farthest drops drawn"},
      {"max_drops",
       ParamType::Integer,
       100000,
       0,
       10000000,
       {},
       "drops",
       "cap on the simulated drops"},
      {"shading",
       ParamType::Enum,
       "default",
       {},
       {},
       {"default", "paper"},
       "",
       "default: environment convolved with the drop's transfer function (about 1 % from a "
       "ray-traced drop); "
       "paper: Wang et al.'s 16 SH coefficients + c B (about 50 %)"},
      {"dispersion",
       ParamType::Boolean,
       false,
       {},
       {},
       {},
       "",
       "per-channel refractive index 1.331 / 1.333 / 1.338"},
      {"background_weight",
       ParamType::Number,
       0.7,
       0.0,
       1.0,
       {},
       "",
       "c in C' = C + c B (Wang et al. Eq. 2); used by shading paper only"},
      {"wind.speed_m_s", ParamType::Number, 0.0, 0.0, 60.0, {}, "m/s", "horizontal wind speed"},
      {"wind.dir_deg",
       ParamType::Number,
       0.0,
       -360.0,
       360.0,
       {},
       "deg",
       "direction the wind blows toward: 0 camera right, 90 away from the camera"},
  };
  info.noOpReason = [](const Preset& p) -> std::string {
    if (p.number("rain.rate_mm_h") == 0.0) return "rate_mm_h is 0";
    if (p.number("rain.density_scale") == 0.0) return "density_scale is 0";
    if (p.number("rain.opacity") == 0.0) return "opacity is 0";
    if (p.number("rain.max_drops") == 0.0) return "max_drops is 0";
    return "";
  };
  info.reads = [](const Preset& p) {
    std::vector<std::string> reads{"image", "depth", "environment"};
    if (p.string("rain.strokes") == "derain") reads.push_back("footage_strokes");
    return reads;
  };
  info.create = [](const Preset& p) { return std::make_unique<RainStage>(p); };
  return info;
}

}  // namespace pluvia
