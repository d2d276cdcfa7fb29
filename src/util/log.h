#pragma once
// Logging to stderr: "pluvia: warning: ...". Thread-safe; the level is process-wide.
#include <string>

namespace pluvia::log {

enum class Level { Quiet = 0, Warning = 1, Info = 2, Debug = 3 };

void setLevel(Level level);
Level level();
void warning(const std::string& message);
void info(const std::string& message);
void debug(const std::string& message);
void error(const std::string& message);

}  // namespace pluvia::log
