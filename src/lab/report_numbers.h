#pragma once
// How the reports (pluvia report ...) print numbers: a missing value (NaN, a failed row) is "-"
// in a table and empty in a CSV.
#include <string>

namespace pluvia::lab {

std::string fixedOrDash(double value, int decimals);  // "1.234" or "-"
std::string percentOrDash(double fraction);           // 0.1234 -> "12.3" or "-"
std::string csvNumber(double value);                  // 6 significant digits, or ""

}  // namespace pluvia::lab
