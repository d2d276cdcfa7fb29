#pragma once
// Writing clips: an image sequence (EXR half with metadata, PNG 8-bit, TIFF 16-bit, DPX 10-bit,
// JPEG) through OpenImageIO, or a movie (mp4/mov through an ffmpeg process, libx264).
// Every sequence frame is written to a temporary file and renamed into place, so a killed job
// never leaves a truncated frame. A movie is encoded to a temporary file and renamed on close().
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "image/image.h"

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

// OUTPUT is a sequence pattern ("out.####.exr", "out.%04d.png") or a movie ("out.mp4").
// Creates the output folder; throws pluvia::Error when the folder cannot be created or written,
// or when the format is unknown.
std::unique_ptr<ClipWriter> openClipWriter(const std::string& output, int width, int height,
                                           const WriterOptions& options);

// True for outputs that should be written as scene-linear (EXR, HDR); others get display encoding.
bool outputIsLinear(const std::string& output);

}  // namespace pluvia
