#include "util/error.h"

#include <fmt/format.h>

#include "util/printable.h"

namespace pluvia {

Error::Error(const std::string& message, ErrorContext context)
    : std::runtime_error(message), context_(std::move(context)) {}

std::string Error::describe() const {
  std::string where;
  if (!context_.stage.empty() || context_.frame) {
    where = "[" + context_.stage;
    if (context_.frame)
      where += fmt::format("{}frame {}", context_.stage.empty() ? "" : " @ ", *context_.frame);
    where += "] ";
  }
  std::string text = where + what();
  // A name may hold control characters (a newline, an escape): shown escaped, as log lines are.
  const std::string file = printable(context_.file);
  if (!file.empty() && text.find(file) == std::string::npos &&
      text.find(context_.file) == std::string::npos) {
    text += fmt::format(" (file: {})", file);
  }
  return text;
}

}  // namespace pluvia
