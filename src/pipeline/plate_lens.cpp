#include "pipeline/plate_lens.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "util/log.h"
#include "util/parse_number.h"

namespace pluvia {

namespace {

const double kFilmDiagonalMm = std::hypot(36.0, 24.0);  // 35 mm film: 43.27 mm
constexpr double kDeg = std::numbers::pi / 180.0;

// The metadata field `name` of `clip` as a number within [low, high], or 0 (said) where it is
// there but states none.
double statedNumber(const ClipInfo& clip, const char* name, double low, double high) {
  const auto it = clip.metadata.find(name);
  if (it == clip.metadata.end()) return 0.0;
  const double value = parseWholeNumber<double>(it->second).value_or(0.0);
  if (std::isfinite(value) && value >= low && value <= high) return value;
  log::warning(fmt::format("plate: {} '{}' in the metadata of {} states no lens: left out", name,
                           it->second, clip.path));
  return 0.0;
}

}  // namespace

PlateLens statedLens(const ClipInfo& clip) {
  const int pictureWidth = clip.displayWindow ? clip.displayWindow->width : clip.width;
  const int pictureHeight = clip.displayWindow ? clip.displayWindow->height : clip.height;
  PlateLens lens;
  std::vector<std::string> parts;
  lens.fNumber = statedNumber(clip, "FNumber", 0.5, 128.0);
  if (lens.fNumber > 0.0) parts.push_back(fmt::format("FNumber {:g}", lens.fNumber));
  lens.focalMm = statedNumber(clip, "Exif:FocalLength", 0.5, 2000.0);
  if (lens.focalMm > 0.0) parts.push_back(fmt::format("FocalLength {:g} mm", lens.focalMm));
  const double equivalentMm = statedNumber(clip, "Exif:FocalLengthIn35mmFilm", 1.0, 5000.0);
  if (equivalentMm > 0.0 && pictureWidth > 0 && pictureHeight > 0) {
    const double aspect = double(pictureWidth) / pictureHeight;
    const double equivalentWidthMm = kFilmDiagonalMm * aspect / std::sqrt(1.0 + aspect * aspect);
    lens.fovDeg = 2.0 * std::atan(0.5 * equivalentWidthMm / equivalentMm) / kDeg;
    parts.push_back(fmt::format("FocalLengthIn35mmFilm {:g} mm", equivalentMm));
  }
  lens.stated = fmt::format("{}", fmt::join(parts, ", "));
  return lens;
}

CameraSettings withPlateLens(const CameraSettings& camera, const PlateLens& lens) {
  if (!camera.lensFromPlate) return camera;
  CameraSettings with = camera;
  if (lens.fovDeg > 0.0) with.fovDeg = lens.fovDeg;
  if (lens.fNumber > 0.0) with.fNumber = lens.fNumber;
  if (lens.focalMm > 0.0)
    with.sensorWidthMm = 2.0 * lens.focalMm * std::tan(0.5 * with.fovDeg * kDeg);
  return with;
}

std::string lensLine(const CameraSettings& camera, const PlateLens& lens) {
  const double focalMm = 0.5 * camera.sensorWidthMm / std::tan(0.5 * camera.fovDeg * kDeg);
  const std::string what = fmt::format(
      "{:.1f} deg view, {}, {:.2f} mm focal length on a {:.2f} mm-wide sensor, focused at {:g} m",
      camera.fovDeg,
      camera.fNumber > 0.0 ? fmt::format("f/{:g}", camera.fNumber) : std::string("a pinhole"),
      focalMm, camera.sensorWidthMm, camera.focusMeters);
  if (lens.stated.empty()) return what + ": the preset's (the plate's files state no lens)";
  if (!camera.lensFromPlate)
    return what + fmt::format(": the preset's (camera.lens_from_plate false; the plate states {})",
                              lens.stated);
  return what + fmt::format(
                    ": the plate's metadata ({}), what it does not state and the focus "
                    "the preset's; camera.lens_from_plate false keeps the preset's",
                    lens.stated);
}

}  // namespace pluvia
