#include "option_values.h"

#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "util/error.h"
#include "util/parse_number.h"

namespace pluvia::cli {

template <class T>
std::vector<T> parseNumberList(const std::string& list, const std::string& option, T min, T max,
                               const std::string& items, const std::string& item) {
  std::vector<T> values;
  std::stringstream in(list);
  std::string text;
  while (std::getline(in, text, ',')) {
    const std::optional<T> value = parseWholeNumber<T>(text);
    if (!value || !(*value >= min && *value <= max)) {
      throw UsageError(fmt::format("{} takes {} from {} to {} separated by commas, got '{}'",
                                   option, items, min, max, text));
    }
    values.push_back(*value);
  }
  if (values.empty()) throw UsageError(fmt::format("{} needs at least one {}", option, item));
  return values;
}
template std::vector<int> parseNumberList(const std::string&, const std::string&, int, int,
                                          const std::string&, const std::string&);
template std::vector<double> parseNumberList(const std::string&, const std::string&, double, double,
                                             const std::string&, const std::string&);

std::pair<int, int> parseFrameSize(const std::string& size, int minSidePx,
                                   const std::string& example) {
  int width = 0, height = 0;
  char x = 0;
  std::stringstream in(size);
  if (!(in >> width >> x >> height) || x != 'x' || !in.eof() || width < minSidePx ||
      height < minSidePx || width > 16384 || height > 16384) {
    throw UsageError("--size takes WIDTHxHEIGHT, e.g. " + example + ", got '" + size + "'");
  }
  return {width, height};
}

}  // namespace pluvia::cli
