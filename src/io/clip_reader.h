#pragma once
// Reading clips: a movie file (an ffmpeg process, at the file's bit depth), an image sequence
// (OpenImageIO: EXR, DPX, TIFF, PNG, JPEG, HDR) or a single image. Frames come back as float RGBA
// in the file's own encoding (no colour conversion here: see image/color.h; a movie can look its
// codes up in a conversion's table as it unpacks them, ClipReader::readCodesThrough), alpha 1
// where absent, grayscale expanded to RGB, 8/16-bit normalised to 0..1, half and float as they are.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "image/color.h"
#include "image/image.h"
#include "io/pixel_window.h"

namespace pluvia {

struct ClipInfo {
  std::string path;             // as given by the user
  std::vector<int64_t> frames;  // frame numbers, in order (sequences keep theirs; movies 0..N-1)
  int width = 0;
  int height = 0;
  double fps = 24.0;  // from the movie; 24 for sequences and stills unless told
  bool isMovie = false;
  bool isFloat = false;   // EXR/HDR/float TIFF: scene-linear by convention
  int channels = 3;       // as stored in the file
  int bitsPerSample = 8;  // as stored: 8, 10, 12, 16 (integer), 16 or 32 (float)
  // What the input says about itself, to be carried to the output, in OpenImageIO's names:
  // "smpte:TimeCode", "Make", "Model", ... (see io/movie_probe.h, io/image_file_reader.h).
  std::map<std::string, std::string> metadata;
  // An EXR's windows, from its first frame. The frame is the display window grown to hold a
  // data window that reaches past it (overscan, kept); displayWindow is then where the picture
  // the camera frames lies in it. dataWindow: the pixels stored, where not the whole frame.
  std::optional<PixelWindow> displayWindow;
  std::optional<PixelWindow> dataWindow;
  std::vector<std::string> files;  // the files read (one for a movie or a still); for hashing
};

class ClipReader {
 public:
  virtual ~ClipReader() = default;
  virtual const ClipInfo& info() const = 0;
  // Reads one frame by its number. Throws pluvia::Error naming the file and frame when the frame
  // is missing, truncated or corrupt, or its size differs from the clip's.
  virtual Image read(int64_t frame) = 0;
  // A hint: these frames (in increasing order) are about to be read. A movie decodes them in
  // one pass that neither converts nor hands over the frames between them, and holds them until
  // each is read. Readers that gain nothing from it ignore it; an error here is left to read().
  virtual void prefetch(const std::vector<int64_t>& frames) {}
  // The bit depth of the integer codes the reader unpacks (8 or 16), or 0 when it cannot look
  // them up in a table (readCodesThrough).
  virtual int codeBits() const { return 0; }
  // read(), with each code looked up in `table` (ColorConverter::codeValues for codeBits()) as
  // it is unpacked instead of normalised: the frame converted without a pass of its own. Only
  // for a reader whose codeBits() is not 0; others read as read() does.
  virtual Image readCodesThrough(int64_t frame, const CodeValues& table) { return read(frame); }
};

// Opens INPUT (movie, sequence pattern, or a single image). Throws pluvia::Error naming the
// path when it does not exist, cannot be decoded, has no frames, or is zero-sized.
std::unique_ptr<ClipReader> openClip(const std::string& input);

}  // namespace pluvia
