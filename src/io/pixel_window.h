#pragma once
// A rectangle of pixels inside a frame (an EXR data window), in frame pixels from the top left.
namespace pluvia {

struct PixelWindow {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
  bool operator==(const PixelWindow&) const = default;
  // Not empty, and wholly inside a frame of frameWidth x frameHeight pixels.
  bool fitsInside(int frameWidth, int frameHeight) const {
    return width > 0 && height > 0 && x >= 0 && y >= 0 && x + width <= frameWidth &&
           y + height <= frameHeight;
  }
};

}  // namespace pluvia
