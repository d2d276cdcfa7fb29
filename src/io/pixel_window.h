#pragma once
// A rectangle of pixels inside a frame (an EXR data window), in frame pixels from the top left.
namespace pluvia {

struct PixelWindow {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
  bool operator==(const PixelWindow&) const = default;
};

}  // namespace pluvia
