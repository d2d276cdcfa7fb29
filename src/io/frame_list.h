#pragma once
// Frame lists as farm tools write them: "1001-1100", "1001-1100x2" (every second frame),
// "1,5,10-20x5" (comma-separated items), "12" (one frame). Negative frame numbers are allowed
// at the start of an item ("-5-5").
#include <cstdint>
#include <string>
#include <vector>

namespace pluvia {

// The frames, ascending, each once. Throws pluvia::UsageError naming the text and the item
// when an item is not NUMBER, FIRST-LAST or FIRST-LASTxSTEP, LAST comes before FIRST, the
// step is not positive, or the list holds more than `maxFrames` frames.
std::vector<int64_t> parseFrameList(const std::string& text, size_t maxFrames = 10'000'000);

// True when `frames` (ascending) are consecutive numbers: a plain range.
bool isContiguous(const std::vector<int64_t>& frames);

}  // namespace pluvia
