// util/fs.h: a finished file that cannot be moved into place is removed and the error names the
// real cause (not "Success", which the cleanup's own error code used to overwrite it with).
#include <gtest/gtest.h>

#include <fstream>

#include "test_support.h"
#include "util/error.h"
#include "util/fs.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(FsCommit, AFailedMoveNamesItsCauseAndLeavesNoTemporary) {
  const stdfs::path dir = freshTempDir("fs_commit");
  const stdfs::path target = dir / "gone" / "frame.0001.png";  // its folder removed meanwhile
  const stdfs::path tmp = fs::temporaryPathFor(dir / "frame.0001.png");
  std::ofstream(tmp) << "pixels";
  try {
    fs::commitTemporary(tmp, target);
    FAIL() << "the move into a missing folder succeeded";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cannot move the finished file into place"), std::string::npos)
        << message;
    EXPECT_EQ(message.find("Success"), std::string::npos) << message;
    EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
  }
  EXPECT_FALSE(stdfs::exists(tmp));
}

TEST(FsCommit, AFolderWhereTheFileGoesIsRefusedAndKept) {
  const stdfs::path dir = freshTempDir("fs_commit_folder");
  const stdfs::path target = dir / "frame.0001.png";
  stdfs::create_directories(target / "occupied");
  const stdfs::path tmp = fs::temporaryPathFor(target);
  std::ofstream(tmp) << "pixels";
  try {
    fs::commitTemporary(tmp, target);
    FAIL() << "the move onto a folder succeeded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder, not a file"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(stdfs::exists(tmp));
  EXPECT_TRUE(stdfs::is_directory(target / "occupied"));
}
