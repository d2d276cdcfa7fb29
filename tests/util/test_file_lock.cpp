// Byte-range lock files (util/file_lock.h) between processes: disjoint ranges are held together,
// an overlapping one is refused naming its holder, a dead holder's range is free, and the last
// holder removes the file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <optional>
#include <thread>

#include "test_support.h"
#include "util/file_lock.h"

using namespace pluvia;
namespace stdfs = std::filesystem;

namespace {

// A child process that holds [start, start + length) of `path` until `release` exists.
// The child's lock, retried for up to 10 s: the parent's probes (waitUntilHeld) hold the range
// for an instant each, and a child refused by one would otherwise give up (a flaky test on a
// loaded machine).
std::optional<FileRangeLock> lockInChild(const std::string& path, off_t start, off_t length) {
  for (int i = 0; i < 2000; ++i) {
    if (auto lock = FileRangeLock::tryLock(path, start, length, nullptr)) return lock;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return std::nullopt;
}

pid_t holdInChild(const std::string& path, off_t start, off_t length, const stdfs::path& release) {
  const pid_t pid = fork();
  if (pid == 0) {
    auto lock = lockInChild(path, start, length);
    if (!lock) _exit(3);
    while (!stdfs::exists(release)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    _exit(0);
  }
  return pid;
}

// Waits (up to 30 s) until a probe of `path` over [start, start + length) is refused and names
// a holder (the child holds it and has written its pid and host after locking).
bool waitUntilHeld(const std::string& path, off_t start, off_t length) {
  for (int i = 0; i < 3000; ++i) {
    LockConflict conflict;
    if (!FileRangeLock::tryLock(path, start, length, &conflict) && !conflict.holder.empty() &&
        conflict.holder != "unknown" && conflict.holder.find(' ') != std::string::npos)
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

}  // namespace

TEST(FileLock, DisjointRangesAreHeldTogetherAndAnOverlapIsRefusedNamingTheHolder) {
  const auto dir = test::freshTempDir("file_lock_ranges");
  const std::string path = (dir / "o.####.png.pluvia-lock").string();
  const pid_t child = holdInChild(path, 640, 128, dir / "release");  // the child's 640..767
  const bool held = waitUntilHeld(path, 640, 1);
  if (!held) std::ofstream(dir / "release").put('x');  // let the child go
  ASSERT_TRUE(held);
  {
    LockConflict conflict;
    auto before = FileRangeLock::tryLock(path, 0, 640, &conflict);  // up to 639: disjoint
    EXPECT_TRUE(before.has_value());
    auto after = FileRangeLock::tryLock(path, 768, 64, &conflict);
    EXPECT_TRUE(after.has_value());
    auto overlap = FileRangeLock::tryLock(path, 700, 200, &conflict);
    EXPECT_FALSE(overlap.has_value());
    EXPECT_EQ(conflict.start, 640);
    EXPECT_EQ(conflict.length, 128);
    EXPECT_EQ(conflict.holder, std::to_string(child) + " " + thisHostName());
  }
  // This process's locks are gone, the child's is held: the file stays for it.
  EXPECT_TRUE(stdfs::exists(path));
  std::ofstream(dir / "release").put('x');
  EXPECT_EQ(test::waitForExit(child), 0);
}

TEST(FileLock, ADeadHoldersRangeIsFreeAndTheLastHolderRemovesTheFile) {
  const auto dir = test::freshTempDir("file_lock_dead");
  const std::string path = (dir / "entry.json.pluvia-lock").string();
  const pid_t child = fork();
  if (child == 0) {
    auto lock = lockInChild(path, 0, 0);
    if (!lock) _exit(3);
    pause();  // killed below while it holds the whole file
    _exit(0);
  }
  const bool held = waitUntilHeld(path, 0, 0);
  kill(child, SIGKILL);  // also when it never held: a paused child would hang the suite
  ASSERT_TRUE(held);
  EXPECT_EQ(test::waitForExit(child), 1000 + SIGKILL);
  // The killed holder left its file, holding nothing.
  ASSERT_TRUE(stdfs::exists(path));
  {
    LockConflict conflict;
    auto lock = FileRangeLock::tryLock(path, 0, 0, &conflict);
    ASSERT_TRUE(lock.has_value()) << "held by " << conflict.holder;
  }
  EXPECT_FALSE(stdfs::exists(path));
}
