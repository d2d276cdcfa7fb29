#pragma once
// Contact sheets for look development (`pluvia preview`): a grid of same-size tiles, each under
// a small label, and the pictures made of a rendered frame's layers to fill it.
#include <string>

#include "image/image.h"

namespace pluvia {

// The rain layer alone (planes "rain.R", "rain.G", "rain.B": the rain's radiance, already
// weighted by its coverage) composited over black, times `gain` so faint rain shows.
// Working-space RGB, alpha 1.
Image rainOverBlack(const Image& frame, float gain);

// The "depth" plane (z-depth, metres) as a grey of 1 / (1 + depth / 10 m): near bright, far
// dark. Sky (+infinity) is a flat dark blue, which no depth gives. Working-space RGB, alpha 1.
Image depthPicture(const Image& frame);

// Tiles of one size in `columns` x `rows` cells, each cell a black label band over its tile.
class ContactSheet {
 public:
  static constexpr int kLabelBandPx = 16;

  ContactSheet(cv::Size tileSize, int columns, int rows);
  // Copies `tile` (RGB already in the sheet's encoding, 0..1; tileSize) into the cell and writes
  // `label` in white in the band above it.
  void place(int row, int column, const Image& tile, const std::string& label);
  const Image& image() const { return sheet_; }

 private:
  cv::Size tileSize_;
  Image sheet_;
};

}  // namespace pluvia
