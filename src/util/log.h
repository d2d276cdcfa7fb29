#pragma once
// Logging to stderr: "pluvia: warning: ...", and to a log file when one is set (--log FILE),
// there with the local time in front. Thread-safe; the level is process-wide.
#include <string>

namespace pluvia::log {

enum class Level { Quiet = 0, Warning = 1, Info = 2, Debug = 3 };

void setLevel(Level level);
Level level();
// Appends every line from now on to `path` too (created when missing), whatever the level: -q
// quiets the terminal, not the file. Throws pluvia::Error naming the file when it cannot be
// opened, and pluvia::UsageError when it exists and is no pluvia log. "" stops.
void setFile(const std::string& path);
// Whether a write to that file failed (it was then closed, with a warning on stderr).
bool fileFailed();
// The --log file being written, or "" when there is none.
std::string filePath();
// Each distinct warning once in the process: the same message again says nothing.
void warning(const std::string& message);
void info(const std::string& message);
void debug(const std::string& message);
void error(const std::string& message);
// A progress line ("progress: frame ...") at the Info level: on a terminal `terminalText`
// rewrites the current line (no newline), elsewhere and in the log file `line` is a line.
void progress(const std::string& line, const std::string& terminalText, bool lastStep);

}  // namespace pluvia::log
