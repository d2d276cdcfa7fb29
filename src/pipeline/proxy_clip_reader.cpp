#include "pipeline/proxy_clip_reader.h"

#include <algorithm>
#include <cmath>

#include "image/resize.h"

namespace pluvia {

ProxyClipReader::ProxyClipReader(std::unique_ptr<ClipReader> fullSize, double scale)
    : fullSize_(std::move(fullSize)), info_(fullSize_->info()) {
  const cv::Size size = scaledSize(info_.width, info_.height, scale);
  // The picture inside an overscan frame scales with it, at least a pixel.
  if (info_.displayWindow) {
    const double sx = double(size.width) / info_.width, sy = double(size.height) / info_.height;
    PixelWindow& picture = *info_.displayWindow;
    const int x0 = int(std::lround(picture.x * sx)), y0 = int(std::lround(picture.y * sy));
    const int x1 = std::max(x0 + 1, int(std::lround((picture.x + picture.width) * sx)));
    const int y1 = std::max(y0 + 1, int(std::lround((picture.y + picture.height) * sy)));
    picture = {x0, y0, std::min(x1, size.width) - x0, std::min(y1, size.height) - y0};
  }
  info_.width = size.width;
  info_.height = size.height;
}

Image ProxyClipReader::read(int64_t frame) {
  return resizeArea(fullSize_->read(frame), {info_.width, info_.height});
}

}  // namespace pluvia
