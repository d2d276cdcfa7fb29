#pragma once
// Stroke libraries: the rain mattes particles carry (Wang et al. section 3), cut from real rain
// footage by `pluvia strokes` (src/derain/stroke_extraction.h).
//
// On disk a library is two files side by side: LIBRARY.json and the atlas it names (a 16-bit
// grayscale PNG). The JSON:
//   {"pluvia_strokes": 1, "atlas": "name.png", "width": W, "height": H,
//    "source": "...", "command": "...",
//    "strokes": [{"rect": [x, y, w, h], "length_px": L, "width_px": w, "contrast": peak alpha,
//                 "source_frame": n, "score": s}, ...]}
// Every stroke in the atlas is vertical (rain rotated upright), its matte scaled to peak 1
// (the renderer sets the opacity from physics; `contrast` keeps the measured peak).
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rain/streak_types.h"
#include "rain/stroke_atlas.h"

namespace pluvia::rain {

struct StrokeInfo {
  int x = 0, y = 0, width = 0, height = 0;  // rectangle in the atlas, pixels
  double lengthPx = 0.0;                    // length of the stroke in its source frame
  double widthPx = 0.0;                     // width across it in its source frame
  double contrast = 0.0;                    // measured peak alpha before normalising
  int64_t sourceFrame = 0;
  double score = 0.0;
};

struct StrokeLibrary {
  StrokeAtlas atlas;  // rects filled from `strokes`
  std::vector<StrokeInfo> strokes;
  std::string source;   // footage it was cut from
  std::string command;  // command line that made it
};

// Writes LIBRARY.json and, beside it, the atlas PNG (same stem). Both files are written to
// temporary names and renamed into place. Throws pluvia::Error naming the path on failure.
void saveStrokeLibrary(const StrokeLibrary& library, const std::string& jsonPath);
// Throws pluvia::Error naming the file (and the key or stroke) when it is missing or invalid:
// rectangles outside the atlas, an atlas of another size than the JSON says, no strokes.
StrokeLibrary loadStrokeLibrary(const std::string& jsonPath);
// A folder searched for assets before the others (the front end sets it from $PLUVIA_ASSET_DIR,
// cli/process_variables.h, before any work); empty: none.
void setAssetFolder(const std::filesystem::path& folder);
// The library shipped with pluvia (assets/strokes/builtin.json in the source tree).
std::string builtinStrokeLibraryPath();

}  // namespace pluvia::rain
