#pragma once
// A display-encoded RGB frame as planar Y'CbCr in a movie codec's own layout (ffmpeg's yuv420p,
// yuv422p, yuv422p10le, yuv444p12le, ...): converted here from float rather than by ffmpeg's
// swscale from 16-bit RGB. Its rgb48 -> yuv420p path costs ~20 ms a 1080p frame on one core, the
// pipe carries a quarter of the bytes, and its RGB48 input scales by 256/255 (white above video
// white at every depth: Y' 235.8 of 235, 943 of 940, 3774 of 3760).
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

// A codec's Y'CbCr: its bit depth and how many columns and rows share a chroma sample.
struct YcbcrLayout {
  int bits = 8;           // 8 (codes in uint8_t), 10 or 12 (in the low bits of uint16_t)
  int chromaColumns = 2;  // 2: 4:2:2 and 4:2:0 (an even width); 1: 4:4:4
  int chromaRows = 2;     // 2: 4:2:0 (an even height); 1: 4:2:2 and 4:4:4
  bool alpha = false;     // an alpha plane after Cr (ffmpeg's yuva...: full range, 0 to 2^bits - 1)
};

// Writes `image` (display-encoded R'G'B', 1 at video white; NaN as 0) into `planes` as
// video-range Y'CbCr of layout.bits, within the legal codes (1 to 254 at 8 bits, 4 to 1019 at
// 10, 16 to 4079 at 12: R'G'B' from -0.068 to 1.087-1.090 keep their super-whites and
// sub-blacks; beyond, they are clamped): the Y' plane of encodedWidth x encodedHeight, then Cb and
// Cr of encodedWidth / chromaColumns x encodedHeight / chromaRows, then with layout.alpha the
// image's alpha as a full plane (A = (2^bits - 1) alpha). Codes round to nearest:
// Y' = (16 + 219 E'y) 2^(bits-8), Cb/Cr = (128 + 224 E'c) 2^(bits-8) (ITU-R BT.709/BT.2020). A
// chroma sample is the mean of the pixels it covers, as swscale's RGB input averages them. An
// encoded size beyond the image's (odd frames made even) repeats its last column and row.
// Chroma rows in parallel (OpenCV's TBB backend), loops the compiler vectorises (5.3 ms of CPU
// a 1080p 4:2:0 frame, against 9.7 for a loop per pixel). Sample: uint8_t for 8 bits, uint16_t
// for 10 and 12 (ffmpeg's ...le formats on a little-endian host).
template <class Sample>
void packYcbcr(const Image& image, int encodedWidth, int encodedHeight, const YcbcrLayout& layout,
               const YcbcrMatrix& matrix, std::vector<Sample>& planes);

}  // namespace pluvia
