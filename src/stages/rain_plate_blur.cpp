#include "stages/rain_plate_blur.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "stages/plate_shutter.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia {

double rainBlurBeyondDrawnPx(double plateStillBlurPx, double minDrawnWidthPx) {
  const double drawn = minDrawnWidthPx / std::sqrt(2.0 * M_PI);
  if (!(plateStillBlurPx > drawn)) return 0.0;
  return std::sqrt(plateStillBlurPx * plateStillBlurPx - drawn * drawn);
}

double rainSofteningPx(ClipContext& clip, double minDrawnWidthPx, bool nightPlate) {
  const double plateBlurPx = clipPlateStillBlurPx(clip);
  const double softeningPx = rainBlurBeyondDrawnPx(plateBlurPx, minDrawnWidthPx);
  if (softeningPx > 0.0 && nightPlate) {
    log::info(
        fmt::format("rain: left as drawn on a night plate (its edges, sigma {:.2f} px, are "
                    "glows and shadows, not the lens's blur)",
                    plateBlurPx));
    return 0.0;
  }
  if (softeningPx > 0.0)
    log::info(
        fmt::format("rain: the plate's still edges are blurred by sigma {:.2f} px: the rain "
                    "is softened by {:.2f} px more than it is drawn",
                    plateBlurPx, softeningPx));
  else if (plateBlurPx > 0.0)
    log::info(
        fmt::format("rain: the plate's still edges (sigma {:.2f} px) are as sharp as the "
                    "rain is drawn: left as drawn",
                    plateBlurPx));
  else
    log::info(
        "rain: left as drawn (the plate's blur was not measured: too few frames or still "
        "edges)");
  return softeningPx;
}

void blurRainOverPlate(Image& frame, const std::vector<float>& plateRgba, double sigmaPx) {
  if (!(sigmaPx > 0.0)) return;
  if (plateRgba.size() != frame.rgba.size())
    throw Error("the plate under the rain differs in size from the frame");
  float* planes[4] = {frame.plane("rain.R").data(), frame.plane("rain.G").data(),
                      frame.plane("rain.B").data(), frame.plane("rain.A").data()};
  for (float* plane : planes) {
    cv::Mat1f view(frame.height, frame.width, plane);
    // Reflected at the border: the layer's light is kept, not spilled off the frame.
    cv::GaussianBlur(view, view, cv::Size(0, 0), sigmaPx, sigmaPx, cv::BORDER_REFLECT);
  }
  float* matte = frame.plane("matte").data();
  for (size_t i = 0; i < frame.pixelCount(); ++i) {
    const float coverage = planes[3][i];
    matte[i] = coverage;
    for (int c = 0; c < 3; ++c) {
      const float plate = plateRgba[i * 4 + c], rain = planes[c][i];
      frame.rgba[i * 4 + c] =
          coverage == 0.0f && rain == 0.0f ? plate : rain + (1.0f - coverage) * plate;
    }
  }
}

}  // namespace pluvia
