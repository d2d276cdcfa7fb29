#include "lab/report_numbers.h"

#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "util/error.h"
#include "util/fs.h"
#include "util/log.h"

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

void writeReportCsv(const std::string& path, const std::string& header,
                    const std::function<void(std::ostream&)>& writeRows) {
  std::ostringstream text;
  text << header << "\n";
  writeRows(text);
  fs::writeTextFile(path, text.str());  // atomic, and never over an input of the run
}

bool runRealPart(const std::string& report, const std::string& what,
                 std::vector<std::string>& notes, const std::function<void()>& part) {
  try {
    part();
    return true;
  } catch (const Error& e) {
    notes.push_back(what + " FAILED: " + e.describe());
    log::warning(report + ": " + what + " failed: " + e.describe());
    return false;
  }
}

}  // namespace pluvia::lab
