#pragma once
// File-system helpers shared by readers, writers and the cache.
#include <cstddef>
#include <filesystem>
#include <string>

namespace pluvia::fs {

// The longest file name ext4, XFS, btrfs and NFS take (NAME_MAX).
constexpr size_t kNameMaxBytes = 255;

// A temporary path beside `target` (same folder, so rename is atomic), keeping the extension
// so that format-sniffing writers still see it: "a.0001.exr" -> "a.0001.pluvia-tmp-<pid>-<n>.exr"
// (a stem too long for that is cut short, so any legal name can be written). `reserveBytes`
// keeps room for a suffix the caller adds to the temporary's name (a movie's ".log").
std::filesystem::path temporaryPathFor(const std::filesystem::path& target,
                                       size_t reserveBytes = 0);

// Throws pluvia::UsageError when `target` exists and is no regular file (a device, a FIFO, a
// folder): renaming a finished image or movie over it would replace it.
void refuseSpecialTarget(const std::filesystem::path& target);

// Renames tmp over target atomically (refuseWritingInput, refuseSpecialTarget first); removes
// tmp and throws pluvia::Error on failure.
void commitTemporary(const std::filesystem::path& tmp, const std::filesystem::path& target);

// Writes `size` bytes to a temporary file beside `target`, flushes them to the disk
// (fdatasync), closes the file and checks that it holds exactly `size` bytes before renaming it
// over `target`. A full disk (ENOSPC), a file size limit (EFBIG) or an I/O error at any step
// removes the temporary and throws pluvia::Error naming `target` and the reason, so a file
// under the target's name is always whole. A FIFO or a character device (/dev/stdout, /dev/null)
// is written through instead, its errors said the same way; a folder or socket is refused.
void writeFileAtomically(const std::filesystem::path& target, const void* bytes, size_t size);

// True when the file at `path` is a temporary (see temporaryPathFor) whose process, by the pid
// in its name, runs no process here (crashed, killed by SIGKILL; or it ran on another host), and
// is no input of this run (input_guard.h) that happens to be named like one.
bool isStaleTemporary(const std::filesystem::path& path);

// Removes the temporaries in `folder` whose names start with `namePrefix` (one output's files:
// "o." for o.####.exr) and whose process is gone (the pid in their name, see temporaryPathFor,
// runs no process here: a render killed by SIGKILL or a crash), with a movie temporary's ffmpeg
// log (isStaleTemporary). Returns how many files were removed.
int removeStaleTemporaries(const std::filesystem::path& folder, const std::string& namePrefix);

// How much of a missing folder ensureParentFolder may make. An output's folder is made only when
// the folder above it exists (LastLevel): a mistyped path must not build a tree of folders
// anywhere, even at /; `--mkdir` asks for every level (All), as pluvia's own cache folder does.
enum class MakeFolders { LastLevel, All };

// Creates the folder that will hold `file` (as `make` allows); throws with the folder named if it
// cannot, or when a level above its last is missing under LastLevel.
void ensureParentFolder(const std::filesystem::path& file, MakeFolders make);

// `path` absolute, with "." and ".." and the links of its existing part resolved: one name for
// one file however it was spelled (relative, through a link). `path` itself if that fails.
std::filesystem::path canonicalSpelling(const std::filesystem::path& path);

// True if two paths name the same existing file (follows links), or the same path when absent.
bool samePath(const std::filesystem::path& a, const std::filesystem::path& b);

std::string readTextFile(const std::filesystem::path& path);
// Throws pluvia::Error when `path` exists but is no regular file: reading a FIFO blocks until a
// writer comes, a device (/dev/zero) never ends, a folder is no file. `what` names the file in
// the message ("the OpenColorIO config").
void requireRegularFile(const std::filesystem::path& path, const std::string& what);
// readTextFile for a file the run reads as its input (a preset, a COLMAP model, a stroke
// library): requireRegularFile, then registered with protectInputs (input_guard.h), so that no
// output, report or log of the run is written over it.
std::string readInputText(const std::filesystem::path& path, const std::string& what);
// Atomic text write (temporary + rename).
void writeTextFile(const std::filesystem::path& path, const std::string& text);

}  // namespace pluvia::fs
