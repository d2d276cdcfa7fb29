#pragma once
// Writing clips: an image sequence (EXR half or float with metadata, PNG 8-bit, TIFF 16-bit,
// DPX 10-bit, JPEG) through OpenImageIO, or a movie (an ffmpeg process: H.264, ProRes 4444 or
// 422 HQ, DNxHR), each tagged with the colour space its RGB is in.
// Every sequence frame is written to a temporary file and renamed into place, so a killed job
// never leaves a truncated frame. A movie is encoded to a temporary file and renamed on close().
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"
#include "io/color_tags.h"
#include "io/output_target.h"
#include "io/pixel_window.h"
#include "io/timecode.h"
#include "util/fs.h"

namespace pluvia {

struct WriterOptions {
  double fps = 24.0;
  // Written into EXR headers (and PNG/TIFF/JPEG text where the format allows, a movie's
  // comment): see pipeline/frame_metadata.h.
  std::map<std::string, std::string> metadata;
  // Extra planes to write as AOVs beside the beauty (e.g. "rain", "matte", "depth"); for EXR
  // they are extra channels of the same file, for other formats separate files
  // "<prefix>.<aov>.<frame><suffix>".
  std::vector<std::string> aovs;
  // Movies: "h264" (mp4/mov/mkv/m4v), "prores_4444", "prores_422hq", "dnxhr_hq", "dnxhr_hqx",
  // "dnxhr_444" (mov/mkv; DNxHR also mxf). See movieCodecs().
  std::string codec = "h264";
  // EXR: "half" or "float" samples, and the compression as OpenImageIO names it (see
  // exrCompressions()).
  std::string exrSampleType = "half";
  std::string exrCompression = "piz";
  // TIFF: "uint16" (clamped to [0, 1]) or "float" samples.
  std::string tiffSampleType = "uint16";
  // The colour space the frames' RGB is in, as the files say it (io/color_tags.h).
  ColorTags color;
  // Whether the beauty keeps an alpha channel where its format holds one: the plate had one.
  // An RGB plate gets no alpha of 1 invented.
  bool alpha = true;
  // The input's timecode at frame `firstFrame`: frame f gets it plus (f - firstFrame). A
  // sequence writes each frame's into its header (EXR, DPX), a movie its first frame's.
  std::optional<Timecode> timecode;
  int64_t firstFrame = 0;
  // EXR: the data window to write, inside the frame (the input's, carried through); pixels
  // outside it are not stored. Empty: the whole frame.
  std::optional<PixelWindow> dataWindow;
  // The picture inside a frame that holds overscan around it (the input's display window,
  // carried through): an EXR keeps the overscan beyond its display window; every other format
  // holds the picture alone, cropped to it. Empty: the frame is the picture.
  std::optional<PixelWindow> displayWindow;
  // The output's folder: made when the folder above it exists, every missing level with --mkdir.
  fs::MakeFolders makeFolders = fs::MakeFolders::LastLevel;
  // Movies: also append the Y'CbCr frames piped to the encoder, byte for byte, to this raw file
  // (`pluvia bench` times the encoder alone on exactly what pluvia gave it). Empty: none.
  std::string ycbcrCopy;
};

class ClipWriter {
 public:
  virtual ~ClipWriter() = default;
  // Writes one frame. Image RGB is already in the output's encoding (colour converted).
  // For movies frames must come in order. Thread-safe for sequences (frames may be written in
  // parallel).
  virtual void write(int64_t frame, const Image& image) = 0;
  // Finishes the clip (movies: closes the encoder and moves the file into place).
  virtual void close() = 0;
  virtual bool isMovie() const = 0;
  // Path the given frame goes to (sequences); the movie path for movies.
  virtual std::string pathFor(int64_t frame) const = 0;
};

// OUTPUT is a sequence pattern ("out.####.exr", "out.%04d.png"), a movie ("out.mp4") or one
// image file. Creates the output folder; throws pluvia::Error when the folder cannot be created
// or written, or when the format is unknown.
std::unique_ptr<ClipWriter> openClipWriter(const OutputTarget& output, int width, int height,
                                           const WriterOptions& options);

// AOVs into a movie output go into movies of their own beside it, with their alpha: an error
// naming `output` when the codec has no alpha or the depth (metres) is asked for. Called by
// openClipWriter, and by a render before any work.
void checkMovieAovs(const std::string& output, const WriterOptions& options);

// Every file a sequence or image output writes for `frame`: the beauty and, for formats that
// cannot hold AOVs as channels, each AOV's own file ("out.####.png" with rain ->
// "out.0001.png", "out.rain.0001.png"). A movie: its own path and its AOVs' ("out.rain.mov").
std::vector<std::string> framePaths(const OutputTarget& output,
                                    const std::vector<std::string>& aovs, int64_t frame);

// True for outputs that should be written as scene-linear (EXR, HDR); others get display encoding.
bool outputIsLinear(const std::string& output);

}  // namespace pluvia
