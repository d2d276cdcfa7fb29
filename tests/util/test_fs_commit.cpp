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
  const stdfs::path target = dir / "frame.0001.png";
  stdfs::create_directories(target / "occupied");  // a non-empty folder where the file should go
  const stdfs::path tmp = fs::temporaryPathFor(target);
  std::ofstream(tmp) << "pixels";
  try {
    fs::commitTemporary(tmp, target);
    FAIL() << "the move onto a folder succeeded";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cannot move the finished file into place"), std::string::npos)
        << message;
    EXPECT_EQ(message.find("Success"), std::string::npos) << message;
    EXPECT_NE(message.find("directory"), std::string::npos) << message;  // EISDIR or ENOTEMPTY
  }
  EXPECT_FALSE(stdfs::exists(tmp));
  EXPECT_TRUE(stdfs::is_directory(target / "occupied"));
}
