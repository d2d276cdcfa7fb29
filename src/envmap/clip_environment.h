#pragma once
// The environment of a shot from its own frames (Wang et al. section 4.1): a panning camera's
// frames stitched into one panorama; a looming or dollying camera gives a view-dependent
// environment every `every` frames (its frame's view: it does not turn), with per-frame SH
// interpolated between them; a static camera's one view.
// Each panorama is projected onto SH of order `shOrder`.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "envmap/panorama.h"
#include "io/clip_reader.h"
#include "optics/sh.h"

namespace pluvia::envmap {

// How the camera moves over the clip, as the stitching takes it: Auto finds it (a rotation found
// by the features is a pan, a changing view a loom, else static).
enum class StitchMotion { Auto, Pan, Loom, Static };

// Its names, the ones presets (lighting.motion) and `pluvia envmap --motion` use.
inline constexpr std::array<std::pair<const char*, StitchMotion>, 4> kStitchMotionNames{
    {{"auto", StitchMotion::Auto},
     {"pan", StitchMotion::Pan},
     {"loom", StitchMotion::Loom},
     {"static", StitchMotion::Static}}};

// "auto", "pan", "loom", "static".
const char* motionName(StitchMotion motion);
// The motion of that name; none for any other.
std::optional<StitchMotion> stitchMotionNamed(const std::string& name);

struct ClipEnvironmentSettings {
  double horizontalFovDeg = 36.0;  // the fallback placement's, and the focal estimate's seed
  StitchMotion motion = StitchMotion::Auto;
  int every = 5;          // loom: a panorama per this many frames
  int maxPanFrames = 24;  // pan: frames taken, evenly over the clip
  int shOrder = 3;
  int width = 512;  // of each panorama (height = width / 2)
  std::vector<LightSource> lights;
  UnseenFill fill = UnseenFill::SkyModel;  // the directions no frame saw (panorama.h)
  std::string inputSpace =
      "auto";  // colour space of the frames (auto: linear for float files, else sRGB)
};

struct EnvironmentKey {
  int64_t frame = 0;          // the clip frame this panorama stands for
  EquirectMap radiance;       // scene-linear, filled everywhere
  optics::ShCoefficients sh;  // of radiance
  double coveredFraction = 0.0;
  bool fromFeatures = false;
};

struct ClipEnvironment {
  std::string motion;                 // what was used: pan, loom or static
  std::vector<EnvironmentKey> keys;   // in frame order, at least one
  std::vector<std::string> warnings;  // fallbacks taken
  double seconds = 0.0;
};

// Throws pluvia::Error naming the input when no frame can be read.
ClipEnvironment buildClipEnvironment(ClipReader& reader, const std::vector<int64_t>& frames,
                                     const ClipEnvironmentSettings& settings);

// Light sources from JSON (the preset's lighting.lights, or a file given to pluvia envmap): a
// list of {"type": "direction", "yaw_deg", "pitch_deg" (from the first frame's view: yaw to the
// right, pitch up), "radius_deg", "radiance": [r, g, b]} and {"type": "region", "frame" (index
// among the frames placed), "x", "y", "width", "height" (pixels), "radiance": [r, g, b]}. Throws
// pluvia::Error naming `source` and the item when invalid.
std::vector<LightSource> parseLights(const nlohmann::json& lights, const std::string& source);

// The result as JSON: motion, order, each key's frame, covered fraction and SH, the per-frame
// SH of every frame in `frames` (interpolated), and the warnings.
nlohmann::json clipEnvironmentJson(const ClipEnvironment& environment,
                                   const std::vector<int64_t>& frames);

// SH at a clip frame: linear between the keys around it, the nearest key's beyond them.
optics::ShCoefficients shAtFrame(const ClipEnvironment& environment, int64_t frame);

}  // namespace pluvia::envmap
