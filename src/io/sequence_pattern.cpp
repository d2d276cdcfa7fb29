#include "io/sequence_pattern.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <limits>
#include <system_error>

#include <fmt/format.h>

#include "util/error.h"

namespace pluvia {
namespace stdfs = std::filesystem;
namespace {

constexpr int kMaxPadding = 19;

// A frame-number token found in a pattern: where it is, how long it is, its padding.
struct Token {
  size_t position = 0;
  size_t length = 0;
  int padding = 0;
};

// The last run of `digit` ('#' or '@'), one character per digit ("####", "@@@@": padding 4).
// ('@' is one digit in OpenImageIO and Houdini too; '#' is one digit here as in Nuke, where
// OpenImageIO reads a single '#' as four.)
std::optional<Token> findRunToken(const std::string& text, char digit) {
  size_t end = text.rfind(digit);
  if (end == std::string::npos) return std::nullopt;
  size_t begin = end;
  while (begin > 0 && text[begin - 1] == digit) --begin;
  return Token{begin, end - begin + 1, static_cast<int>(end - begin + 1)};
}

// The later of two tokens (either may be absent).
std::optional<Token> later(std::optional<Token> a, std::optional<Token> b) {
  if (!a || (b && b->position > a->position)) return b;
  return a;
}

// The last "%d" or "%0Nd" ("%04d": padding 4). "%4d" (space padding) is not a frame token.
std::optional<Token> findPrintfToken(const std::string& text) {
  for (size_t at = text.rfind('%'); at != std::string::npos;
       at = at == 0 ? std::string::npos : text.rfind('%', at - 1)) {
    size_t cursor = at + 1;
    int padding = 0;
    if (cursor < text.size() && text[cursor] == '0') {
      size_t digitsBegin = ++cursor;
      while (cursor < text.size() && std::isdigit(static_cast<unsigned char>(text[cursor])))
        ++cursor;
      if (cursor == digitsBegin) continue;
      if (std::from_chars(text.data() + digitsBegin, text.data() + cursor, padding).ec !=
          std::errc())
        padding = std::numeric_limits<int>::max();  // refused by parse()
    }
    if (cursor < text.size() && text[cursor] == 'd') return Token{at, cursor + 1 - at, padding};
  }
  return std::nullopt;
}

}  // namespace

std::optional<SequencePattern> SequencePattern::parse(const std::string& text) {
  // Two kinds in one string is odd; the last one is taken, since frame numbers live in the
  // file name rather than in a folder name.
  const std::optional<Token> token =
      later(later(findRunToken(text, '#'), findRunToken(text, '@')), findPrintfToken(text));
  if (!token) return std::nullopt;
  // A frame number has at most 19 digits: a longer padding only makes gigantic names (and a
  // 100 MB error message for '%0100000000d').
  if (token->padding > kMaxPadding)
    throw Error(
        fmt::format("the sequence pattern '{}...' pads frame numbers to {} digits: at most {}",
                    text.substr(0, std::min<size_t>(text.size(), token->position + 8)),
                    token->padding, kMaxPadding),
        {{}, {}, text.substr(0, 200)});
  SequencePattern pattern;
  pattern.prefix = text.substr(0, token->position);
  pattern.suffix = text.substr(token->position + token->length);
  pattern.padding = token->padding;
  return pattern;
}

std::string SequencePattern::pathFor(int64_t frame) const {
  return prefix + fmt::format("{:0{}d}", frame, padding) + suffix;
}

std::vector<int64_t> SequencePattern::existingFrames() const {
  stdfs::path prefixPath(prefix);
  // "plate." has no folder part; "shots/" has an empty file-name part.
  stdfs::path folder = prefixPath.has_filename() ? prefixPath.parent_path() : prefixPath;
  std::string namePrefix = prefixPath.has_filename() ? prefixPath.filename().string() : "";
  std::vector<int64_t> frames;
  std::error_code ec;
  stdfs::directory_iterator it(folder.empty() ? stdfs::path(".") : folder, ec);
  if (ec) return frames;
  for (const stdfs::directory_entry& entry : it) {
    std::string name = entry.path().filename().string();
    if (name.size() <= namePrefix.size() + suffix.size()) continue;
    if (!name.starts_with(namePrefix) || !name.ends_with(suffix)) continue;
    std::string_view digits(name.data() + namePrefix.size(),
                            name.size() - namePrefix.size() - suffix.size());
    if (digits.size() > 18 ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      continue;
    }
    int64_t frame = 0;
    std::from_chars(digits.data(), digits.data() + digits.size(), frame);
    // Only names pathFor() would produce: "0001" for ####, also "10000", but not "1" or "00001".
    if (fmt::format("{:0{}d}", frame, padding) != digits) continue;
    if (!entry.is_regular_file(ec)) continue;
    frames.push_back(frame);
  }
  std::sort(frames.begin(), frames.end());
  return frames;
}

std::string lowerExtension(const std::string& path) {
  std::string extension = stdfs::path(path).extension().string();
  if (!extension.empty()) extension.erase(0, 1);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

bool isMovieExtension(const std::string& path) {
  static const std::array<std::string, 7> kMovieExtensions{"mp4", "mov",  "avi", "mkv",
                                                           "m4v", "webm", "mxf"};
  std::string extension = lowerExtension(path);
  return std::find(kMovieExtensions.begin(), kMovieExtensions.end(), extension) !=
         kMovieExtensions.end();
}

}  // namespace pluvia
