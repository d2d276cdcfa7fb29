// Byte-range lock files (util/file_lock.h) between processes: disjoint ranges are held together,
// an overlapping one is refused naming its holder, a dead holder's range is free, and the last
// holder removes the file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <thread>

#include "test_support.h"
#include "util/file_lock.h"

using namespace pluvia;
namespace stdfs = std::filesystem;

namespace {

// A child process that holds [start, start + length) of `path` until `release` exists.
pid_t holdInChild(const std::string& path, off_t start, off_t length, const stdfs::path& release) {
  const pid_t pid = fork();
  if (pid == 0) {
    auto lock = FileRangeLock::tryLock(path, start, length, nullptr);
    if (!lock) _exit(3);
    while (!stdfs::exists(release)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    _exit(0);
  }
  return pid;
}

// Waits until a probe of `path` over [start, start + length) is refused (the child holds it).
bool waitUntilHeld(const std::string& path, off_t start, off_t length) {
  for (int i = 0; i < 500; ++i) {
    LockConflict conflict;
    if (!FileRangeLock::tryLock(path, start, length, &conflict)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

}  // namespace

TEST(FileLock, DisjointRangesAreHeldTogetherAndAnOverlapIsRefusedNamingTheHolder) {
  const auto dir = test::freshTempDir("file_lock_ranges");
  const std::string path = (dir / "o.####.png.pluvia-lock").string();
  const pid_t child = holdInChild(path, 640, 128, dir / "release");  // the child's 640..767
  ASSERT_TRUE(waitUntilHeld(path, 640, 1));
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
    auto lock = FileRangeLock::tryLock(path, 0, 0, nullptr);
    pause();  // killed below while it holds the whole file
    _exit(lock ? 0 : 3);
  }
  ASSERT_TRUE(waitUntilHeld(path, 0, 0));
  kill(child, SIGKILL);
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
