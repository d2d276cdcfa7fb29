#include "stages/lighting_settings.h"

#include "util/error.h"

namespace pluvia {
namespace {

// lighting.motion's names: the stitcher's own (envmap/clip_environment.h).
std::vector<EnumName<envmap::StitchMotion>> motionNames() {
  std::vector<EnumName<envmap::StitchMotion>> names;
  for (const auto& [name, value] : envmap::kStitchMotionNames) names.push_back({name, value});
  return names;
}

ParamSpec lightsParam() {
  // Item fields take plain numbers within +-1e9.
  const NumberRange any{-1e9, 1e9};
  const ParamSpec radiance =
      colorParam("radiance", nlohmann::json::array({1, 1, 1}), "linear", "measured radiance");
  ParamSpec lights = listParam(
      "lights", nlohmann::json::array(),
      {{"direction",
        {numberParam("yaw_deg", 0.0, any, "deg", "to the right of the first frame's view"),
         numberParam("pitch_deg", 45.0, any, "deg", "above the horizon"),
         numberParam("radius_deg", 0.5, any, "deg", "angular radius"), radiance}},
       {"region",
        {integerParam("frame", 0, any, "", "index of the frame among those stitched"),
         integerParam("x", 0, any, "px", "left edge in that frame"),
         integerParam("y", 0, any, "px", "top edge in that frame"),
         integerParam("width", 1, any, "px", "width"),
         integerParam("height", 1, any, "px", "height"), radiance}}},
      "stitch: light sources the footage saturated, given their measured radiance");
  return lights;
}

}  // namespace

const SettingsTable<LightingSettings>& lightingTable() {
  using S = LightingSettings;
  static const SettingsTable<LightingSettings> table(
      {.name = "lighting",
       .help = "Environment lighting for the drops (per clip): an equirect HDR, a constant, or the "
               "clip's average.",
       .inputs = {"still"},
       .outputs = {"environment"}},
      {
          bind(&S::enabled, enabledParam()),
          bind(&S::source, "source",
               {{"frame", LightingSource::Frame},
                {"frame_average", LightingSource::FrameAverage},
                {"constant", LightingSource::Constant},
                {"hdr", LightingSource::Hdr},
                {"stitch", LightingSource::Stitch}},
               "frame: the plate itself within the camera's view, its mean by elevation elsewhere "
               "(the sky above lights the drops); stitch: the shot's frames stitched into a "
               "panorama (Wang et al. 4.1); frame_average: mean radiance of sampled frames in "
               "every direction; constant: lighting.color; hdr: lighting.hdr"),
          // Qualified: std::vector in the arguments brings std::bind in by argument lookup.
          pluvia::bind(&S::motion, "motion", motionNames(),
                       "stitch: the camera's motion (auto: rotation found by the features makes "
                       "a pan, a changing view a loom)"),
          bind(&S::everyFrames, integerParam("every", 5, {1, 10000}, "frames",
                                             "stitch, loom: a panorama every N frames")),
          bind(&S::panFrames, integerParam("pan_frames", 24, {1, 500}, "frames",
                                           "stitch, pan: frames stitched, evenly over the clip")),
          bind(&S::unseenFill, "unseen_fill",
               {{"sky_model", envmap::UnseenFill::SkyModel},
                {"nearest", envmap::UnseenFill::Nearest}},
               "stitch: the directions no frame saw; sky_model: a Preetham, CIE "
               "overcast or uniform sky fitted to the seen sky and the seen ground's "
               "albedo under it; nearest: the nearest seen colour (Wang et al.)"),
          bind(&S::lights, lightsParam()),
          bind(&S::hdrPath,
               pathParam("hdr", "",
                         "equirect HDR (.exr, .hdr; linear Rec.709; +Y up, image centre looking "
                         "along -Z) for source hdr")),
          bind(&S::intensity, numberParam("intensity", 1.0, {0.0, 1e6}, "",
                                          "scale on the HDR's radiance, to match the plate")),
          bind(&S::constantRgb, colorParam("color", nlohmann::json::array({0.5, 0.5, 0.5}),
                                           "linear", "radiance when source is constant")),
          bind(&S::sampleFrames,
               integerParam("sample_frames", 8, {1, 1000}, "frames",
                            "frames averaged for frame_average (frame takes the median of 5 over "
                            "the clip)")),
      });
  return table;
}

LightingSettings lightingSettings(const Preset& p) {
  LightingSettings s = lightingTable().read(p);
  // Said where the preset is read, so that `pluvia validate` says it as the render does.
  if (s.source == LightingSource::Hdr && s.hdrPath.empty())
    throw Error("lighting.source is \"hdr\" but lighting.hdr names no file", {"lighting"});
  return s;
}

}  // namespace pluvia
