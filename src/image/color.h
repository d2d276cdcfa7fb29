#pragma once
// Colour management through OpenColorIO. The config is the one at `configPath`, else the one
// $OCIO names (as every OCIO application does), else pluvia's own, built in code from OCIO's
// built-in transforms (Debian's OCIO 2.1 has no built-in config). Colour spaces are named by
// their names, their aliases or a role ("scene_linear").
// Colour spaces of the built-in config:
//   "linear-rec709"  scene-linear, Rec.709 primaries (the default working space)
//   "ACEScg"         scene-linear, AP1 primaries
//   "sRGB"           sRGB transfer curve, Rec.709 primaries (PNG, JPEG, video by default)
//   "rec709"         Rec.709 camera OETF, Rec.709 primaries
//   "raw"            no conversion
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"

namespace pluvia {

// Integer-coded samples converted by table: entry k of channel c is what a conversion makes of
// the value k / (2^bits - 1) (as the clip readers normalise codes) in that channel.
using CodeValues = std::array<std::vector<float>, 3>;

// What the clip readers multiply a `bits`-bit code by to normalise it to 0..1; codeValues()
// normalises its codes the same way, so a table entry is the conversion of the very value read.
constexpr float codeScale(int bits) {
  return 1.0f / static_cast<float>((1 << bits) - 1);
}

class ColorConverter {
 public:
  // Throws pluvia::Error naming the colour space when one is unknown.
  ColorConverter(const std::string& from, const std::string& to,
                 const std::string& configPath = "");
  ~ColorConverter();
  ColorConverter(ColorConverter&&) noexcept;
  ColorConverter& operator=(ColorConverter&&) noexcept;
  // Converts RGB in place (alpha and planes untouched).
  void apply(Image& image) const;
  bool isNoOp() const;
  // The table of every `bits`-bit code (8 or 16) converted as apply() converts it, when each
  // channel converts alone (a transfer curve, or nothing to do); empty otherwise (channel
  // crosstalk: a matrix) or for other depths.
  std::optional<CodeValues> codeValues(int bits) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The config file used for `configPath`: itself, else $OCIO, else "" (the built-in config).
std::string chosenConfigPath(const std::string& configPath);
// The config used, for logs: "PATH", "PATH (from $OCIO)" or "pluvia's built-in config".
std::string describeConfig(const std::string& configPath);
// A space's name in the config, then its aliases. Throws pluvia::Error when it is unknown.
std::vector<std::string> colorSpaceNamesOf(const std::string& name,
                                           const std::string& configPath = "");
// The config's space for display-encoded sRGB files (PNG, JPEG, 8-bit movies): "sRGB" or its
// usual names in the ACES configs, or the texture_paint role. Throws when there is none.
std::string srgbEncodedSpace(const std::string& configPath = "");
// The config's space for video encoded with the Rec.709 camera OETF (which BT.601 and SDR
// BT.2020 share) on `primaries` as ffmpeg names them ("bt709", "bt2020"; others are taken as
// Rec.709's): "rec709" / "rec2020" in the built-in config, their usual names in the ACES
// configs; nothing when the config has no such space.
std::optional<std::string> videoEncodedSpace(const std::string& primaries,
                                             const std::string& configPath = "");

// Names of the colour spaces available (built-in config or the given one).
std::vector<std::string> colorSpaceNames(const std::string& configPath = "");

// The version of the OpenColorIO library pluvia runs with ("2.1.2").
std::string colorLibraryVersion();

// Writes the built-in config as an .ocio file (so users can inspect or extend it).
void saveBuiltinConfig(const std::string& path);

}  // namespace pluvia
