#include "lab/report_numbers.h"

#include <cmath>

#include <fmt/format.h>

namespace pluvia::lab {

std::string fixedOrDash(double value, int decimals) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, decimals) : "-";
}

std::string percentOrDash(double fraction) {
  return fixedOrDash(100.0 * fraction, 1);
}

std::string csvNumber(double value) {
  return std::isfinite(value) ? fmt::format("{:.6g}", value) : "";
}

}  // namespace pluvia::lab
