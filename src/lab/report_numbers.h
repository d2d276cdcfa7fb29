#pragma once
// How the reports (pluvia report ...) print numbers and write their CSVs: a missing value (NaN, a
// failed row) is "-" in a table and empty in a CSV. And how a part of a report on real data fails.
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

namespace pluvia::lab {

std::string fixedOrDash(double value, int decimals);  // "1.234" or "-"
std::string percentOrDash(double fraction);           // 0.1234 -> "12.3" or "-"
std::string csvNumber(double value);                  // 6 significant digits, or ""

// A measure a row does not have.
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Writes a report's CSV to `path`: the `header` line, then what `writeRows` writes. Throws
// pluvia::Error naming the file when it cannot be opened or written.
void writeReportCsv(const std::string& path, const std::string& header,
                    const std::function<void(std::ostream&)>& writeRows);

// Runs `part`, a report's part on real data, and returns true; a pluvia::Error it throws is
// reported, not hidden, and does not stop the synthetic part that stands on its own: the note
// "<what> FAILED: <error>", a warning "<report>: <what> failed: <error>", and false.
bool runRealPart(const std::string& report, const std::string& what,
                 std::vector<std::string>& notes, const std::function<void()>& part);

}  // namespace pluvia::lab
