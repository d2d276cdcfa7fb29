// Looking programs up on PATH without a shell (issue 16: $PLUVIA_COLMAP reached `sh -c`).
#include <gtest/gtest.h>

#include <cstdlib>

#include "sfm/colmap_runner.h"
#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::sfm;
namespace stdfs = std::filesystem;

TEST(ProgramLookup, FindsProgramsOnPathAndByPath) {
  EXPECT_TRUE(programAvailable("sh"));
  EXPECT_TRUE(programAvailable("/bin/sh"));
  EXPECT_FALSE(programAvailable("no-such-program-pluvia"));
  EXPECT_FALSE(programAvailable(""));
  EXPECT_FALSE(programAvailable("/etc"));  // a folder is not a program
}

TEST(ProgramLookup, ANameIsNeverRunAsACommandLine) {
  const stdfs::path dir = test::freshTempDir("program_lookup");
  const std::string pwned = (dir / "pwned").string();
  EXPECT_FALSE(programAvailable("x;touch " + pwned));
  EXPECT_FALSE(programAvailable("$(touch " + pwned + ")"));
  sfm::setColmapProgram("x;touch " + pwned);  // as $PLUVIA_COLMAP sets it
  EXPECT_FALSE(sfm::colmapAvailable(""));
  sfm::setColmapProgram("");
  EXPECT_FALSE(stdfs::exists(pwned));
}
