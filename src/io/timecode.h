#pragma once
// SMPTE timecode ("01:00:00:00"; ';' before the frames marks drop-frame counting) as a frame
// count, so that a clip's first timecode gives every later frame's. Drop-frame timecodes are
// counted as they are labelled only for 29.97 and 59.94 (the drop-frame rates); arithmetic
// on other rates is plain.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace pluvia {

struct Timecode {
  int64_t frames = 0;  // since 00:00:00:00
  int rate = 24;       // frames per second, rounded (30 for 29.97)
  bool dropFrame = false;

  // nullopt when `text` is not HH:MM:SS:FF (or HH:MM:SS;FF) with FF below the rate.
  static std::optional<Timecode> parse(const std::string& text, double fps);
  // The text of an EXR/DPX/OIIO timecode's first word (SMPTE 12M BCD time and flags):
  // "HH:MM:SS:FF", or "HH:MM:SS;FF" with the drop-frame flag.
  static std::string textOfSmpteWord(uint32_t timeAndFlags);
  Timecode plus(int64_t frameCount) const;
  std::string text() const;  // "01:00:00:00", wrapping at 24 hours
  // The SMPTE 12M words: time and flags (BCD; bit 6 drop-frame), user data (0).
  std::array<uint32_t, 2> smpteWords() const;
};

}  // namespace pluvia
