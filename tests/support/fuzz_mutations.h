#pragma once
// Seeded mutations of text and bytes for the fuzz tests: each case is reproducible from its
// seed and index, and printed when it fails.
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace pluvia::test {

class Mutator {
 public:
  explicit Mutator(uint32_t seed) : random_(seed) {}

  size_t below(size_t n) {
    return n == 0 ? 0 : std::uniform_int_distribution<size_t>(0, n - 1)(random_);
  }
  template <typename T>
  const T& pick(const std::vector<T>& items) {
    return items[below(items.size())];
  }

  // Values chosen to break parsers and arithmetic.
  std::string hostileValue() {
    static const std::vector<std::string> kValues{
        "1e308",
        "-1e308",
        "1e400",
        "-0",
        "NaN",
        "Infinity",
        "99999999999999999999999",
        "-99999999999999999999999",
        "0.0000000000000000000001",
        "\"\"",
        "\"x\"",
        "null",
        "true",
        "[]",
        "{}",
        "[[0,0]]",
        "[[0,1],[0,2]]",
        "[[1e308,0],[-1e308,1]]",
        "{\"keys\": []}",
        "{\"keys\": [[0, 1]], \"interpolation\": \"cubic\"}",
        "[1,2]",
        "[1e6,1e6,1e6]",
        "\"/dev/zero\"",
        "\"/etc/passwd\"",
        "\"\\u0000\"",
        "[" + std::string(100, '[') + std::string(100, ']') + "]",
        "{\"a\":" + std::string(70, '[') + std::string(70, ']') + "}",
        "6",
        "-1",
        "0",
        "65505",
        "1e15",
        "1e16",
        "4294967296",
        "-2147483649"};
    return pick(kValues);
  }

  // One random edit of JSON-like text: a byte flipped, a character inserted or removed, a
  // range deleted or duplicated, or a number or string replaced by a hostile value.
  std::string mutateText(std::string text) {
    static const std::string kChars = "{}[]\",:.-+eE0123456789 \n\\tfnu";
    const size_t edits = 1 + below(3);
    for (size_t e = 0; e < edits; ++e) {
      const size_t at = below(text.size() + 1);
      switch (below(7)) {
        case 0:
          if (!text.empty()) text[below(text.size())] ^= static_cast<char>(1u << below(8));
          break;
        case 1:
          text.insert(at, 1, kChars[below(kChars.size())]);
          break;
        case 2:
          if (at < text.size()) text.erase(at, 1 + below(8));
          break;
        case 3:
          if (at < text.size()) text.insert(at, text.substr(at, 1 + below(40)));
          break;
        case 4:
        case 5: {  // a value after a ':' replaced
          const size_t colon = text.find(':', at);
          if (colon == std::string::npos) break;
          const size_t end = text.find_first_of(",}\n", colon + 1);
          // Appended, not " " + value: GCC 12 warns falsely on that (-Wrestrict, its bug 105651).
          std::string value(1, ' ');
          value += hostileValue();
          text.replace(colon + 1, end == std::string::npos ? 0 : end - colon - 1, value);
          break;
        }
        default:
          text = text.substr(0, at);  // truncated
          break;
      }
    }
    return text;
  }

  // Bytes truncated, or with a few bits flipped in the first `headerBytes`.
  std::string mutateBytes(std::string bytes, size_t headerBytes) {
    if (below(2) == 0) return bytes.substr(0, below(std::min(bytes.size(), headerBytes * 4)));
    const size_t flips = 1 + below(4);
    const size_t span = std::min(bytes.size(), headerBytes);
    for (size_t i = 0; i < flips && span > 0; ++i)
      bytes[below(span)] ^= static_cast<char>(1u << below(8));
    return bytes;
  }

 private:
  std::mt19937 random_;
};

}  // namespace pluvia::test
