#pragma once
// Test images written through OpenImageIO with a header the test chooses (a data window apart
// from the display window, channel names, attributes, the stored sample type): what
// writeImageFile in test_support.h does not let a test set.
#include <filesystem>

#include <OpenImageIO/imageio.h>

namespace pluvia::test {

// A spec of width x height pixels of `channels` samples stored as `format`, whose data window
// starts at (x, y) inside a display window of displayWidth x displayHeight at the origin.
OIIO::ImageSpec windowedSpec(int width, int height, int channels, OIIO::TypeDesc format, int x,
                             int y, int displayWidth, int displayHeight);

// Writes `samples` (interleaved, of `dataType`) under `spec` to `path`; a failure fails the test
// with OpenImageIO's message.
void writeWithSpec(const std::filesystem::path& path, const OIIO::ImageSpec& spec,
                   const void* samples, OIIO::TypeDesc dataType = OIIO::TypeDesc::FLOAT);

}  // namespace pluvia::test
