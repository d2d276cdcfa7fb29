#pragma once
// Option values that several commands parse the same way; free of pluvia's pipeline so that
// pluvia-bench-strokes links without it.
#include <string>
#include <utility>
#include <vector>

namespace pluvia::cli {

// A comma-separated list of numbers, each from `min` to `max` (--lod 0,0.5,1; --strokes
// 1000,10000), for T int or double. Throws UsageError naming `option`, `items` and the bad item
// ("--strokes takes counts from 1 to 10000000 separated by commas, got '1e3'"), or `item` for an
// empty list ("--strokes needs at least one count").
template <class T>
std::vector<T> parseNumberList(const std::string& list, const std::string& option, T min, T max,
                               const std::string& items, const std::string& item);
// WIDTHxHEIGHT (--size 720x480), each side from `minSidePx` to 16384. Throws UsageError quoting
// `example` and the text.
std::pair<int, int> parseFrameSize(const std::string& size, int minSidePx,
                                   const std::string& example);

}  // namespace pluvia::cli
