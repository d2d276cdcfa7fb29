#include "image/contact_sheet.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace pluvia {
namespace {

// Depth at which the depth picture is half as bright as at the lens.
constexpr float kDepthHalfBrightMeters = 10.0f;
// Sky in the depth picture: dark blue (linear), darker than any grey it would be confused with.
constexpr float kSkyRgb[3] = {0.0f, 0.01f, 0.08f};

}  // namespace

Image rainOverBlack(const Image& frame, float gain) {
  Image out(frame.width, frame.height);
  const char* names[3] = {"rain.R", "rain.G", "rain.B"};
  for (int c = 0; c < 3; ++c) {
    const std::vector<float>* rain = frame.findPlane(names[c]);
    if (!rain) continue;  // no rain drawn: black
    for (size_t i = 0; i < out.pixelCount(); ++i) out.rgba[i * 4 + c] = gain * (*rain)[i];
  }
  return out;
}

Image depthPicture(const Image& frame) {
  Image out(frame.width, frame.height);
  const std::vector<float>* depth = frame.findPlane(kDepthPlane);
  for (size_t i = 0; i < out.pixelCount(); ++i) {
    const float meters = depth ? (*depth)[i] : INFINITY;
    float* rgb = out.rgba.data() + i * 4;
    if (std::isfinite(meters)) {
      const float grey = 1.0f / (1.0f + std::max(meters, 0.0f) / kDepthHalfBrightMeters);
      rgb[0] = rgb[1] = rgb[2] = grey;
    } else {
      for (int c = 0; c < 3; ++c) rgb[c] = kSkyRgb[c];
    }
  }
  return out;
}

ContactSheet::ContactSheet(cv::Size tileSize, int columns, int rows)
    : tileSize_(tileSize),
      sheet_(columns * tileSize.width, rows * (kLabelBandPx + tileSize.height)) {}

void ContactSheet::place(int row, int column, const Image& tile, const std::string& label) {
  if (tile.width != tileSize_.width || tile.height != tileSize_.height)
    throw std::invalid_argument("contact sheet: a tile of another size");
  const int left = column * tileSize_.width;
  const int bandTop = row * (kLabelBandPx + tileSize_.height);
  cv::Mat sheet = sheet_.rgbaMat();
  const cv::Mat source(tile.height, tile.width, CV_32FC4, const_cast<float*>(tile.rgba.data()));
  source.copyTo(sheet(cv::Rect(left, bandTop + kLabelBandPx, tile.width, tile.height)));
  // Hershey simplex at 0.4 is about 9 px tall: it fits the band with room above and below.
  const cv::Point baseline(left + 4, bandTop + kLabelBandPx - 4);
  cv::putText(sheet, label, baseline, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(1, 1, 1, 1), 1,
              cv::LINE_AA);
}

}  // namespace pluvia
