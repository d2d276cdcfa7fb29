#pragma once
// A display-encoded RGB frame as 8-bit planar Y'CbCr, the layout ffmpeg's yuv420p and yuv422p
// hold, for 8-bit movie codecs: converted here from float rather than by ffmpeg's swscale from
// 16-bit RGB (its rgb48 -> yuv420p path costs ~20 ms a 1080p frame on one core, and the pipe
// carries a quarter of the bytes).
#include <cstdint>
#include <string>
#include <vector>

#include "image/image.h"

namespace pluvia {

// Luma weights of red and blue (the matrix's Kr and Kb): green's is 1 - kr - kb.
struct YcbcrMatrix {
  float kr = 0.0f;
  float kb = 0.0f;
};

// The matrix ffmpeg names "bt709" or "bt2020nc" (-colorspace, io/color_tags.h); "" is BT.709.
// Another name is an error naming it and `path`.
YcbcrMatrix ycbcrMatrix(const std::string& ffmpegName, const std::string& path);

// Writes `image` (RGB in [0, 1], clamped, NaN as 0, and rounded to 16 bits) into `planes` as
// video-range 8-bit Y'CbCr: Y' plane of encodedWidth x encodedHeight, then Cb and Cr at half the
// width, and at half the height too when `halfHeightChroma` (4:2:0; else 4:2:2). Codes round to
// nearest: Y' = 16 + 219 E'y, Cb/Cr = 128 + 224 E'c (ITU-R BT.709/BT.2020). A chroma sample is the
// mean of the 2 (4:2:2) or 2x2 (4:2:0) pixels it covers, as swscale's RGB input averages pixel
// pairs. An encoded size beyond the image's (odd frames made even) repeats its last column and row.
// Chroma rows in parallel (OpenCV's TBB backend), loops the compiler vectorises (5.3 ms of CPU
// a 1080p frame, against 9.7 for a loop per pixel).
void packYcbcr8(const Image& image, int encodedWidth, int encodedHeight, bool halfHeightChroma,
                const YcbcrMatrix& matrix, std::vector<uint8_t>& planes);

}  // namespace pluvia
