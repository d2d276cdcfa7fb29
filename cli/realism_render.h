#pragma once
// `pluvia report realism`'s renders: a preset over the clean plates of real rain footage, by the
// render's own session (the same stages and preset resolution as `pluvia render`), with darken,
// blur and fog off so that the streaks alone are compared. Here in cli, not lab: rendering is the
// stages' work.
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "temporary_folder.h"

namespace pluvia::cli {

// Plates written once as a temporary PNG sequence (removed with the object), with a per-clip
// analysis cache beside them (--cache), so that renders of several looks on the same plates
// (`pluvia match`'s candidates) make the lighting, the depth guess and the lamps search once.
class PlateRenderer {
 public:
  // `plates`: RGB, 8-bit display codes as float 0-255, frames 0.. of a clip at `fps`, standing
  // for footage filmed `filmedWidthPx` wide: rain.far_m 0 draws the rain as deep as that camera
  // sees it, not as the plates' measuring width would (a 1280 px clip measured at 640 px shows
  // its rain twice as deep as a 640 px camera would).
  PlateRenderer(const std::vector<cv::Mat3f>& plates, double fps, int filmedWidthPx);
  // The rained frames in the plates' encoding, rounded to codes; darken, blur and fog off.
  std::vector<cv::Mat3f> render(const std::string& preset,
                                const std::vector<std::string>& sets) const;

 private:
  TemporaryFolder folder_;
  double fps_;
  int filmedWidthPx_;
};

// `plates`: RGB, 8-bit display codes as float 0-255, frames 0.. of a clip at `fps`. Returns the
// rained frames in the same encoding, rounded to codes. The plates go through a temporary PNG
// sequence (removed afterwards), read as sRGB as any 8-bit plate is.
std::vector<cv::Mat3f> renderOnPlates(const std::vector<cv::Mat3f>& plates, double fps,
                                      int filmedWidthPx, const std::string& preset,
                                      const std::vector<std::string>& sets);

}  // namespace pluvia::cli
