#pragma once
// The files a run reads as its input (the plate's frames, an HDR, a depth file) are never
// written by it, whatever option names the file written: the main output, an AOV's own file, a
// report, a CSV or the log. Commands register their inputs before any work; every file write
// (fs::writeFileAtomically, fs::commitTemporary, the --log file) asks here first.
#include <filesystem>
#include <string>
#include <vector>

namespace pluvia::fs {

// Remembers each existing file by its device and inode, so a symlink, a hard link or a "../"
// spelling of it is recognised too. Files that do not exist are skipped.
void protectInputs(const std::vector<std::string>& files);

// The input file `target` is (by device and inode, following links), or "" when it is none of
// them (or does not exist).
std::string protectedInputAt(const std::filesystem::path& target);

// Throws pluvia::UsageError naming `target` and the input when writing `target` would replace or
// change an input file.
void refuseWritingInput(const std::filesystem::path& target);

}  // namespace pluvia::fs
