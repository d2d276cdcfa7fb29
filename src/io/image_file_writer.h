#pragma once
// Writing one image file through OpenImageIO, atomically (encoded in memory, written to a
// temporary file, flushed, checked and renamed: see fs::writeFileAtomically), in the
// sample encoding its extension calls for: EXR half (float where asked), HDR float, PNG/JPEG
// 8-bit, TIFF 16-bit, DPX 10-bit.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/color_tags.h"
#include "io/pixel_window.h"
#include "io/timecode.h"

namespace pluvia {

// One channel of the file, gathered from pluvia's buffers.
struct OutputChannel {
  std::string name;        // "R", "rain.R", "depth.Z"
  const float* samples;    // the first pixel's sample
  size_t strideFloats;     // between pixels: 4 inside an RGBA buffer, 1 in a plane
  bool fullFloat = false;  // EXR: 32-bit float instead of half (depth in metres)
};

// How a file is written beyond its extension's defaults.
struct ImageFileOptions {
  bool exrFullFloat = false;           // EXR: every channel 32-bit float instead of half
  bool tiffFloat = false;              // TIFF: 32-bit float samples instead of 16-bit codes
  std::string exrCompression = "piz";  // EXR: as OpenImageIO names it (exrCompressions())
  const ColorTags* color = nullptr;    // the colour space: EXR chromaticities, oiio:ColorSpace,
                                       // DPX transfer and colorimetric fields
  std::optional<Timecode> timecode;    // EXR and DPX headers
  // EXR: the data window (inside the frame); only its pixels are stored. Others: ignored.
  std::optional<PixelWindow> dataWindow;
  // EXR: the display window (inside the frame) where the frame holds overscan around it: the
  // file's display window is it, and its data window reaches past it. Others: ignored.
  std::optional<PixelWindow> displayWindow;
};

// EXR compressions ImageFileOptions::exrCompression may name.
const std::vector<std::string>& exrCompressions();

// Extensions writeImageFile() accepts, lower case.
const std::vector<std::string>& imageOutputExtensions();

// Integer encodings clamp to 0..1 and round to the nearest code; float encodings keep values
// (NaN and Inf included; half clamps finite values to +-65504). String metadata goes into the
// header where the format has room. Throws pluvia::Error naming the file (and frame).
void writeImageFile(const std::string& path, int width, int height,
                    const std::vector<OutputChannel>& channels,
                    const std::map<std::string, std::string>& metadata,
                    std::optional<int64_t> frame, const ImageFileOptions& options = {});

}  // namespace pluvia
