#include "io/frame_list.h"

#include <algorithm>
#include <charconv>

#include <fmt/format.h>

#include "util/error.h"

namespace pluvia {
namespace {

// A whole string as an integer (an optional leading '-', then digits); false otherwise.
bool parseInteger(std::string_view text, int64_t& value) {
  if (text.empty()) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && end == text.data() + text.size();
}

}  // namespace

std::vector<int64_t> parseFrameList(const std::string& text, size_t maxFrames) {
  auto fail = [&](std::string_view item, const std::string& why) {
    return UsageError(fmt::format(
        "--frames '{}': {} in '{}' (expected FIRST-LAST, FIRST-LASTxSTEP or a comma list such "
        "as 1001-1100x2,1150)",
        text, why, item));
  };
  std::vector<int64_t> frames;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string_view item = std::string_view(text).substr(
        start, comma == std::string::npos ? text.npos : comma - start);
    // The range's dash is the first '-' after the first character (which may be a minus sign).
    const size_t x = item.find('x');
    const std::string_view range = item.substr(0, x);
    const size_t dash = range.size() > 1 ? range.find('-', 1) : std::string_view::npos;
    int64_t first = 0, last = 0, step = 1;
    if (!parseInteger(range.substr(0, dash), first)) throw fail(item, "no frame number");
    last = first;
    if (dash != std::string_view::npos && !parseInteger(range.substr(dash + 1), last))
      throw fail(item, "no last frame number");
    if (x != std::string_view::npos) {
      if (dash == std::string_view::npos) throw fail(item, "a step without a range");
      if (!parseInteger(item.substr(x + 1), step) || step <= 0)
        throw fail(item, "the step is not a whole number above 0");
    }
    if (last < first) throw fail(item, "the last frame comes before the first");
    if (static_cast<uint64_t>(last - first) / static_cast<uint64_t>(step) >= maxFrames)
      throw fail(item, fmt::format("more than {} frames", maxFrames));
    for (int64_t frame = first; frame <= last; frame += step) {
      frames.push_back(frame);
      if (last - frame < step) break;  // no overflow past INT64_MAX
    }
    if (frames.size() > maxFrames) throw fail(item, fmt::format("more than {} frames", maxFrames));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  return frames;
}

bool isContiguous(const std::vector<int64_t>& frames) {
  return frames.empty() ||
         frames.back() - frames.front() + 1 == static_cast<int64_t>(frames.size());
}

}  // namespace pluvia
