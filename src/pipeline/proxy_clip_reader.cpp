#include "pipeline/proxy_clip_reader.h"

#include "image/resize.h"

namespace pluvia {

ProxyClipReader::ProxyClipReader(std::unique_ptr<ClipReader> fullSize, double scale)
    : fullSize_(std::move(fullSize)), info_(fullSize_->info()) {
  const cv::Size size = scaledSize(info_.width, info_.height, scale);
  info_.width = size.width;
  info_.height = size.height;
}

Image ProxyClipReader::read(int64_t frame) {
  return resizeArea(fullSize_->read(frame), {info_.width, info_.height});
}

}  // namespace pluvia
