#include "io/color_tags.h"

#include <algorithm>
#include <cctype>

namespace pluvia {
namespace {

// Lower case, only letters and digits: "Linear Rec.709 (sRGB)" -> "linearrec709srgb".
std::string squashed(const std::string& name) {
  std::string out;
  for (unsigned char c : name)
    if (std::isalnum(c)) out += static_cast<char>(std::tolower(c));
  return out;
}

bool has(const std::string& text, const char* part) {
  return text.find(part) != std::string::npos;
}

// CIE xy of the primaries and white (ITU-R BT.709, BT.2020; SMPTE ST 2065-1 for AP0,
// S-2014-004 for AP1; SMPTE EG 432-1 for P3-D65).
constexpr std::array<float, 8> kRec709{0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
constexpr std::array<float, 8> kRec2020{0.708f, 0.292f, 0.170f,  0.797f,
                                        0.131f, 0.046f, 0.3127f, 0.3290f};
constexpr std::array<float, 8> kAp0{0.7347f, 0.2653f, 0.0f,     1.0f,
                                    0.0001f, -0.077f, 0.32168f, 0.33767f};
constexpr std::array<float, 8> kAp1{0.713f, 0.293f, 0.165f,   0.830f,
                                    0.128f, 0.044f, 0.32168f, 0.33767f};
constexpr std::array<float, 8> kP3D65{0.680f, 0.320f, 0.265f,  0.690f,
                                      0.150f, 0.060f, 0.3127f, 0.3290f};

}  // namespace

ColorTags colorTagsFor(const std::vector<std::string>& names) {
  ColorTags tags;
  if (names.empty()) return tags;
  tags.name = names.front();
  for (const std::string& name : names) {
    const std::string s = squashed(name);
    if (s.empty()) continue;
    const bool linear =
        has(s, "lin") || has(s, "scenelinear") || has(s, "acescg") || has(s, "aces2065");
    const bool srgbCurve = has(s, "srgb") && !has(s, "linear") && !has(s, "lin");
    // Primaries: the first family the name belongs to.
    if (has(s, "aces2065") || has(s, "ap0")) {
      tags.chromaticities = kAp0;
    } else if (has(s, "acescg") || has(s, "acescc") || has(s, "acescct") || has(s, "ap1")) {
      tags.chromaticities = kAp1;
    } else if (has(s, "2020")) {
      tags.chromaticities = kRec2020;
      tags.moviePrimaries = "bt2020";
      tags.movieMatrix = "bt2020nc";
      tags.dpxColorimetric = "ITU-R 2020 NCL";
    } else if (has(s, "p3d65") || has(s, "displayp3")) {
      tags.chromaticities = kP3D65;
      tags.moviePrimaries = "smpte432";
      tags.movieMatrix = "bt709";
    } else if (has(s, "709") || has(s, "srgb") || has(s, "bt1886")) {
      tags.chromaticities = kRec709;
      tags.moviePrimaries = "bt709";
      tags.movieMatrix = "bt709";
      tags.dpxColorimetric = "ITU-R 709-4";
    } else {
      continue;
    }
    // Transfer.
    if (linear) {
      tags.linear = true;
      tags.movieTransfer = "linear";
      tags.dpxTransfer = "Linear";
    } else if (srgbCurve) {
      tags.movieTransfer = "iec61966-2-1";
      tags.dpxTransfer = "User defined";
    } else if (has(s, "1886") || has(s, "gamma24")) {
      tags.movieTransfer = "bt709";  // BT.1886 displays decode BT.709-tagged video this way
      tags.dpxTransfer = "ITU-R 709-4";
    } else if (has(s, "709") || has(s, "2020")) {
      tags.movieTransfer = has(s, "2020") ? "bt2020-10" : "bt709";
      tags.dpxTransfer = has(s, "2020") ? "ITU-R 2020 NCL" : "ITU-R 709-4";
    }
    return tags;
  }
  return tags;
}

ColorTags linearAovTags() {
  ColorTags tags;
  tags.name = "linear";
  tags.movieTransfer = "linear";
  tags.linear = true;
  return tags;
}

}  // namespace pluvia
