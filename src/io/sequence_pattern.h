#pragma once
// Image-sequence patterns: "plate.####.exr" or "plate.@@@@.exr" (one # or @ per digit, padded)
// and "plate.%04d.png".
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pluvia {

struct SequencePattern {
  std::string prefix;  // everything before the frame number (folder included)
  std::string suffix;  // everything after it
  int padding = 0;     // minimum digits (0: no padding)

  // Parses "####", "@@@@" or "%0Nd"/"%d"; nullopt when the string holds no frame-number token.
  static std::optional<SequencePattern> parse(const std::string& text);
  std::string pathFor(int64_t frame) const;
  // Frame numbers of existing files that match the pattern, sorted.
  std::vector<int64_t> existingFrames() const;
};

// True for file names that denote a movie container we write or read as one file.
bool isMovieExtension(const std::string& path);
// Lower-case extension without the dot ("exr").
std::string lowerExtension(const std::string& path);

}  // namespace pluvia
