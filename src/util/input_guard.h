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

// Records `target` as a file this run writes under `option` ("-o", "--report", "--log"), and
// throws pluvia::UsageError when another option of the run already writes it (`--log
// o/r.0002.png` beside `-o o/r.####.png`): one of the two would be lost. Paths are compared
// after making them absolute and resolving links, so two spellings of one file collide.
void claimOutput(const std::filesystem::path& target, const std::string& option);

}  // namespace pluvia::fs
