#pragma once
// What a render writes, told once from the path it was given: a movie ("out.mp4"), an image
// sequence ("out.####.exr", "out.%04d.png") or one image file ("still.png"). The writer, the
// output lock, --skip-existing and the farm take this instead of each reading the string again.
#include <cstdint>
#include <optional>
#include <string>

#include "io/sequence_pattern.h"

namespace pluvia {

struct OutputTarget {
  enum class Kind { Movie, Sequence, SingleImage };

  // A movie extension makes a movie whatever the name holds (as an input is read); otherwise a
  // frame-number token makes a sequence. Throws pluvia::Error for a token padded beyond 19 digits.
  static OutputTarget classify(const std::string& path);

  Kind kind = Kind::SingleImage;
  std::string path;                        // as given
  std::optional<SequencePattern> pattern;  // a sequence's, set for Kind::Sequence only

  bool isMovie() const { return kind == Kind::Movie; }
  bool isSequence() const { return kind == Kind::Sequence; }
  // The file frame `frame` goes to: the sequence's, else the path itself (every frame of a movie
  // or of one image file goes to that one file).
  std::string pathFor(int64_t frame) const { return pattern ? pattern->pathFor(frame) : path; }
};

}  // namespace pluvia
