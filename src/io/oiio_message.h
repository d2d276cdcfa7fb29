#pragma once
// OpenImageIO's error text as one line for pluvia's errors (it stacks a line per layer:
// "Read error: hit end of file\nPNG read error: ...").
#include <string>

namespace pluvia {

inline std::string oiioMessage(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (size_t at = text.find('\n'); at != std::string::npos; at = text.find('\n', at))
    text.replace(at, 1, "; ");
  return text.empty() ? "(no reason given)" : text;
}

}  // namespace pluvia
