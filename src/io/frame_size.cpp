#include "io/frame_size.h"

#include <fmt/format.h>

namespace pluvia {

void checkFrameSize(int64_t width, int64_t height, const std::string& path,
                    const ErrorContext& context) {
  if (width > kMaxFrameSidePx || height > kMaxFrameSidePx || width * height > kMaxFramePixels)
    throw Error(fmt::format("{} claims {}x{} pixels ({:.0f} Mpx): over pluvia's limit of {} px a "
                            "side and {:.0f} Mpx a frame (a corrupt header, or a frame to split "
                            "or scale first)",
                            path, width, height, double(width) * double(height) / 1e6,
                            kMaxFrameSidePx, double(kMaxFramePixels) / 1e6),
                context);
}

}  // namespace pluvia
