#include "io/timecode.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>

namespace pluvia {
namespace {

constexpr int64_t kDay = 24 * 3600;

struct Fields {
  int64_t hours, minutes, seconds, frames;
};

// Frames dropped from the count in the minutes before this one: 2 (4 at 59.94) a minute except
// every tenth minute.
int64_t droppedBefore(int64_t totalMinutes, int dropPerMinute) {
  return dropPerMinute * (totalMinutes - totalMinutes / 10);
}

int64_t toFrames(const Fields& f, int rate, bool dropFrame) {
  int64_t frames = ((f.hours * 60 + f.minutes) * 60 + f.seconds) * rate + f.frames;
  if (dropFrame) frames -= droppedBefore(f.hours * 60 + f.minutes, rate / 15);
  return frames;
}

Fields toFields(int64_t frames, int rate, bool dropFrame) {
  frames %= kDay * rate;
  if (frames < 0) frames += kDay * rate;
  if (dropFrame) {
    // Labels skipped: add back what was dropped before this frame (SMPTE 12M counting).
    const int64_t drop = rate / 15;
    const int64_t perTenMinutes = 600 * rate - 9 * drop;
    const int64_t perMinute = 60 * rate - drop;
    const int64_t tens = frames / perTenMinutes;
    const int64_t rest = frames % perTenMinutes;
    frames += 9 * drop * tens + (rest > drop ? drop * ((rest - drop) / perMinute) : 0);
  }
  return {frames / (3600 * rate), frames / (60 * rate) % 60, frames / rate % 60, frames % rate};
}

int bcd(int64_t value) {
  return static_cast<int>((value / 10) << 4 | (value % 10));
}

int fromBcd(uint32_t bits) {
  return static_cast<int>((bits >> 4) * 10 + (bits & 15));
}

}  // namespace

std::optional<Timecode> Timecode::parse(const std::string& text, double fps) {
  int h = 0, m = 0, s = 0, f = 0;
  char separator = ':';
  int used = 0;
  if (std::sscanf(text.c_str(), "%d:%d:%d%c%d%n", &h, &m, &s, &separator, &f, &used) != 5 ||
      used != static_cast<int>(text.size()) ||
      (separator != ':' && separator != ';' && separator != '.')) {
    return std::nullopt;
  }
  Timecode tc;
  tc.rate = std::max(1, static_cast<int>(std::lround(fps)));
  tc.dropFrame = separator != ':' && (tc.rate == 30 || tc.rate == 60);
  if (h < 0 || h > 23 || m < 0 || m > 59 || s < 0 || s > 59 || f < 0 || f >= tc.rate)
    return std::nullopt;
  tc.frames = toFrames({h, m, s, f}, tc.rate, tc.dropFrame);
  return tc;
}

std::string Timecode::textOfSmpteWord(uint32_t word) {
  return fmt::format("{:02}:{:02}:{:02}{}{:02}", fromBcd((word >> 24) & 0x3f),
                     fromBcd((word >> 16) & 0x7f), fromBcd((word >> 8) & 0x7f),
                     (word & 0x40) ? ';' : ':', fromBcd(word & 0x3f));
}

Timecode Timecode::plus(int64_t frameCount) const {
  Timecode tc = *this;
  tc.frames = ((frames + frameCount) % (kDay * rate) + kDay * rate) % (kDay * rate);
  return tc;
}

std::string Timecode::text() const {
  const Fields f = toFields(frames, rate, dropFrame);
  return fmt::format("{:02}:{:02}:{:02}{}{:02}", f.hours, f.minutes, f.seconds,
                     dropFrame ? ';' : ':', f.frames);
}

std::array<uint32_t, 2> Timecode::smpteWords() const {
  const Fields f = toFields(frames, rate, dropFrame);
  const uint32_t word = static_cast<uint32_t>(bcd(f.hours)) << 24 |
                        static_cast<uint32_t>(bcd(f.minutes)) << 16 |
                        static_cast<uint32_t>(bcd(f.seconds)) << 8 |
                        static_cast<uint32_t>(bcd(f.frames)) | (dropFrame ? 0x40u : 0u);
  return {word, 0u};
}

}  // namespace pluvia
