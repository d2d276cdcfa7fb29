#include "io/frame_list.h"

#include <algorithm>

#include <fmt/format.h>

#include "util/error.h"
#include "util/parse_number.h"

namespace pluvia {
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
    const std::optional<int64_t> firstNumber = parseWholeNumber<int64_t>(range.substr(0, dash));
    if (!firstNumber) throw fail(item, "no frame number");
    const std::optional<int64_t> lastNumber =
        dash == std::string_view::npos ? firstNumber
                                       : parseWholeNumber<int64_t>(range.substr(dash + 1));
    if (!lastNumber) throw fail(item, "no last frame number");
    std::optional<int64_t> stepNumber = 1;
    if (x != std::string_view::npos) {
      if (dash == std::string_view::npos) throw fail(item, "a step without a range");
      stepNumber = parseWholeNumber<int64_t>(item.substr(x + 1));
      if (!stepNumber || *stepNumber <= 0)
        throw fail(item, "the step is not a whole number above 0");
    }
    const int64_t first = *firstNumber, last = *lastNumber, step = *stepNumber;
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
