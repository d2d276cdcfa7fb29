#include "oiio_files.h"

#include <gtest/gtest.h>

namespace pluvia::test {

OIIO::ImageSpec windowedSpec(int width, int height, int channels, OIIO::TypeDesc format, int x,
                             int y, int displayWidth, int displayHeight) {
  OIIO::ImageSpec spec(width, height, channels, format);
  spec.x = x;
  spec.y = y;
  spec.full_x = 0;
  spec.full_y = 0;
  spec.full_width = displayWidth;
  spec.full_height = displayHeight;
  return spec;
}

void writeWithSpec(const std::filesystem::path& path, const OIIO::ImageSpec& spec,
                   const void* samples, OIIO::TypeDesc dataType) {
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out) << path << ": " << OIIO::geterror();
  ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(dataType, samples)) << out->geterror();
  ASSERT_TRUE(out->close()) << out->geterror();
}

}  // namespace pluvia::test
