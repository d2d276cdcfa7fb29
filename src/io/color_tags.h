#pragma once
// What an output file says about its colour, from the name (and aliases) of the colour space
// its RGB is in: EXR chromaticities, OpenImageIO's "oiio:ColorSpace", DPX transfer and
// colorimetric fields, and a movie's colour tags. Names are matched against the usual spellings
// of ACES, OCIO and facility configs ("ACEScg", "lin_ap1", "Linear Rec.709 (sRGB)",
// "sRGB - Texture", "Rec.1886 Rec.709 - Display", "lin_rec2020", "Linear P3-D65"); a space none
// matches is named in "oiio:ColorSpace" only.
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace pluvia {

struct ColorTags {
  std::string name;  // "oiio:ColorSpace": the space's name in its config ("" for none)
  // EXR "chromaticities": red, green, blue and white x, y.
  std::optional<std::array<float, 8>> chromaticities;
  // ffmpeg's -color_primaries, -color_trc, -colorspace values ("" for unspecified).
  std::string moviePrimaries;
  std::string movieTransfer;
  std::string movieMatrix;
  // OpenImageIO's DPX "dpx:Transfer" and "dpx:Colorimetric" ("" for none).
  std::string dpxTransfer;
  std::string dpxColorimetric;
  bool linear = false;  // a scene-linear or linear display space
};

// The tags for a space known by these names (its name first, then its aliases).
ColorTags colorTagsFor(const std::vector<std::string>& names);

// The tags of an AOV's own file or movie: its values are the working space's, linear (a
// premultiplied layer, a matte, a signed change), whatever the beauty's output space. A PNG
// gets gAMA 1.0 ("oiio:ColorSpace" "linear"), a movie color_trc linear.
ColorTags linearAovTags();

}  // namespace pluvia
