// Files a run must not write through (adversarial S8, S11, S12, S15): a lock file that is a
// symlink or a second name of another file is refused, not written into; a protected input is
// refused to every atomic write and to the log, by any of its names; control characters in a
// message are shown escaped.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "test_support.h"
#include "util/error.h"
#include "util/file_lock.h"
#include "util/fs.h"
#include "util/input_guard.h"
#include "util/log.h"
#include "util/printable.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(GuardedFiles, ALockFileThatIsALinkIsRefusedAndItsTargetKept) {
  const stdfs::path dir = freshTempDir("guard_lock");
  const stdfs::path victim = writeTextFile(dir, "victim.txt", std::string(200, 'v'));
  stdfs::create_symlink(victim, dir / "a.lock");
  EXPECT_THROW(FileRangeLock::tryLock((dir / "a.lock").string(), 64, 64, nullptr), Error);
  EXPECT_EQ(fs::readTextFile(victim), std::string(200, 'v'));
  // Dangling: nothing is created where it points.
  stdfs::create_symlink(dir / "elsewhere" / "created", dir / "b.lock");
  stdfs::create_directories(dir / "elsewhere");
  EXPECT_THROW(FileRangeLock::tryLock((dir / "b.lock").string(), 0, 64, nullptr), Error);
  EXPECT_FALSE(stdfs::exists(dir / "elsewhere" / "created"));
  // A hard link to another file.
  stdfs::create_hard_link(victim, dir / "c.lock");
  EXPECT_THROW(FileRangeLock::tryLock((dir / "c.lock").string(), 0, 64, nullptr), Error);
  EXPECT_EQ(fs::readTextFile(victim), std::string(200, 'v'));
  // A plain lock file still works.
  EXPECT_TRUE(FileRangeLock::tryLock((dir / "d.lock").string(), 0, 64, nullptr).has_value());
}

TEST(GuardedFiles, AProtectedInputIsNeverWrittenByAnyOfItsNames) {
  const stdfs::path dir = freshTempDir("guard_inputs");
  const stdfs::path plate = writeTextFile(dir, "plate.0001.png", std::string("\x89PNG\0\0", 6));
  stdfs::create_symlink(plate, dir / "link.png");
  stdfs::create_hard_link(plate, dir / "hard.png");
  const stdfs::path other = writeTextFile(dir, "other.txt", "x");
  fs::protectInputs({plate.string()});
  for (const stdfs::path& name : {plate, dir / "link.png", dir / "hard.png",
                                  dir / ".." / dir.filename() / "plate.0001.png"}) {
    EXPECT_THROW(fs::writeTextFile(name, "report"), UsageError) << name;
    EXPECT_EQ(fs::protectedInputAt(name), plate.string()) << name;
  }
  EXPECT_EQ(fs::readTextFile(plate), std::string("\x89PNG\0\0", 6));
  EXPECT_NO_THROW(fs::writeTextFile(other, "y"));
  EXPECT_NO_THROW(fs::writeTextFile(dir / "new.txt", "z"));
  EXPECT_THROW(log::setFile((dir / "hard.png").string()), UsageError);
}

TEST(GuardedFiles, TheLogAppendsOnlyToAPluviaLog) {
  const stdfs::path dir = freshTempDir("guard_log");
  const stdfs::path image = writeTextFile(dir, "frame.exr", std::string("v/1\x01\0\0\0", 7));
  EXPECT_THROW(log::setFile(image.string()), UsageError);
  EXPECT_EQ(fs::readTextFile(image).size(), 7u);
  // Text that is no log (a colour config, a LUT, a COLMAP model) is refused too.
  const stdfs::path text = writeTextFile(dir, "notes.txt", "earlier notes\n");
  EXPECT_THROW(log::setFile(text.string()), UsageError);
  EXPECT_EQ(fs::readTextFile(text), "earlier notes\n");
  const stdfs::path earlier =
      writeTextFile(dir, "run.log", "2026-12-01 10:00:00 pluvia: an earlier run\n");
  EXPECT_NO_THROW(log::setFile(earlier.string()));
  log::info("this run");
  log::setFile("");
  const std::string logged = fs::readTextFile(earlier);
  EXPECT_EQ(logged.rfind("2026-12-01 10:00:00 pluvia: an earlier run\n", 0), 0u) << logged;
  EXPECT_NE(logged.find(" pluvia: this run\n"), std::string::npos) << logged;
}

TEST(GuardedFiles, ControlCharactersAreShownEscaped) {
  EXPECT_EQ(printable("a\x1b]0;title\x07z"), "a\\x1b]0;title\\x07z");
  EXPECT_EQ(printable("two\nlines\tand\x7f", true), "two\nlines\tand\\x7f");
  EXPECT_EQ(printable("two\nlines"), "two\\x0alines");
  EXPECT_EQ(printable("pluie \xc3\xa0 Paris"), "pluie \xc3\xa0 Paris");  // UTF-8 kept
}
