// Every file a run reads is an input, protected as the plate is (adversarial pass, issue 59):
// an HDR or a lights file named as the output, a text file of the user's as the --log, a preset
// where the output's lock goes, plate frames named like a killed render's temporaries. Each case
// overwrote, appended to or deleted the input before; each now fails with the file named (or, for
// the temporaries, renders) and leaves the input as it was.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <regex>
#include <sstream>

#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(CliEveryInputProtected, AnHdrTheOutputNamesIsRefusedBeforeAnyWork) {
  const stdfs::path dir = freshTempDir("protect_hdr");
  const std::string plate = writeTexturedPlate(dir, 1, 2);
  writeImageFile(dir / "env.exr", flatImage(64, 32, 0.4f, 0.5f, 0.7f));
  const std::string before = fs::readTextFile(dir / "env.exr");
  const auto r = runPluvia({"render", plate, "-p", "drizzle", "--frames", "1", "-o",
                            (dir / "env.exr").string(), "--set", "lighting.source=hdr", "--set",
                            "lighting.hdr=" + (dir / "env.exr").string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  expectOutputHas(r.output, {"env.exr is the input file", "refusing to overwrite it"});
  EXPECT_EQ(fs::readTextFile(dir / "env.exr"), before);
}

TEST(CliEveryInputProtected, TheLogNeverAppendsToAFileThatIsNoLog) {
  const stdfs::path dir = freshTempDir("protect_log");
  const std::string plate = writeTexturedPlate(dir, 1, 1);
  // A colour config, a stroke library's JSON, COLMAP's images.txt: text the run may read later.
  const stdfs::path notes = writeTextFile(dir, "config.ocio", "ocio_profile_version: 2\n");
  const auto r = runPluvia({"render", plate, "-p", "drizzle", "-o",
                            (dir / "o" / "r.####.png").string(), "--log", notes.string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  expectOutputHas(r.output, {"config.ocio is not a pluvia log", "refusing to append"});
  EXPECT_EQ(fs::readTextFile(notes), "ocio_profile_version: 2\n");
  EXPECT_FALSE(stdfs::exists(dir / "o" / "r.0001.png"));

  // A pluvia log is appended to; -q quiets the terminal, never the log.
  const stdfs::path log = dir / "run.log";
  for (int run = 0; run < 2; ++run) {
    const auto q = runPluvia({"render", plate, "-p", "drizzle", "-o",
                              (dir / "o" / "r.####.png").string(), "-q", "--log", log.string()});
    ASSERT_EQ(q.exitCode, 0) << q.output;
    EXPECT_EQ(q.output.find("progress:"), std::string::npos) << q.output;
  }
  // Both runs' messages and progress lines, each stamped (a message's own further lines, as
  // the plan's, follow it unstamped).
  const std::string logged = fs::readTextFile(log);
  const std::regex stamped(R"(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d pluvia: progress: frame 1 .*)");
  std::istringstream lines(logged);
  size_t progress = 0;
  for (std::string line; std::getline(lines, line);) progress += std::regex_match(line, stamped);
  EXPECT_EQ(progress, 2u) << logged;
}

TEST(CliEveryInputProtected, APresetWhereTheLockGoesIsNeitherWrittenNorDeleted) {
  const stdfs::path dir = freshTempDir("protect_lock");
  const std::string plate = writeTexturedPlate(dir, 1, 1);
  stdfs::create_directories(dir / "o");
  const stdfs::path preset =
      writeTextFile(dir / "o", "r.png.pluvia-lock", R"({"pluvia": 1, "extends": "drizzle"})");
  const std::string before = fs::readTextFile(preset);
  const auto r =
      runPluvia({"render", plate, "-p", preset.string(), "-o", (dir / "o" / "r.png").string()});
  EXPECT_NE(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"r.png.pluvia-lock is an input file of this run"});
  ASSERT_TRUE(stdfs::exists(preset));
  EXPECT_EQ(fs::readTextFile(preset), before);
}

TEST(CliEveryInputProtected, PlateFramesNamedLikeTemporariesAreReadNotDeleted) {
  const stdfs::path dir = freshTempDir("protect_temporaries");
  stdfs::create_directories(dir / "src");
  writeTexturedPlate(dir / "src", 1, 2);
  ASSERT_FALSE(stdfs::exists("/proc/999999"));  // the "killed render" of their names is gone
  for (int f = 1; f <= 2; ++f) {
    const std::string name = "r.000" + std::to_string(f) + ".pluvia-tmp-999999-0.png";
    stdfs::copy_file(dir / "src" / ("plate.000" + std::to_string(f) + ".png"), dir / name);
  }
  const auto r = runPluvia({"render", (dir / "r.####.pluvia-tmp-999999-0.png").string(), "-p",
                            "drizzle", "-o", (dir / "r.####.png").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "r.0001.pluvia-tmp-999999-0.png"));
  EXPECT_TRUE(stdfs::exists(dir / "r.0002.pluvia-tmp-999999-0.png"));
  EXPECT_TRUE(stdfs::exists(dir / "r.0002.png"));
}

TEST(CliEveryInputProtected, OneRunNeverWritesOneFileTwice) {
  const stdfs::path dir = freshTempDir("protect_collide");
  const std::string plate = writeTexturedPlate(dir, 1, 3);
  // --log onto the render's own frame 2.
  stdfs::create_directories(dir / "o");
  const auto log =
      runPluvia({"render", plate, "-p", "drizzle", "-o", (dir / "o" / "r.####.png").string(),
                 "--mkdir", "--log", (dir / "o" / "r.0002.png").string()});
  EXPECT_EQ(log.exitCode, 2) << log.output;
  expectOutputHas(log.output, {"r.0002.png would be written twice", "--log", "-o"});
  EXPECT_FALSE(stdfs::exists(dir / "o" / "r.0001.png"));

  // derain's --report over its own clean frame 2; --matte-out onto its clean frames.
  const auto report = runPluvia({"derain", plate, "-o", (dir / "d" / "c.####.png").string(),
                                 "--report", (dir / "d" / "c.0002.png").string()});
  EXPECT_EQ(report.exitCode, 2) << report.output;
  expectOutputHas(report.output, {"would be written twice", "--report"});
  const auto matte = runPluvia({"derain", plate, "-o", (dir / "e" / "c.####.png").string(),
                                "--matte-out", (dir / "e" / "./c.####.png").string()});
  EXPECT_EQ(matte.exitCode, 2) << matte.output;
  expectOutputHas(matte.output, {"would be written twice", "--matte-out"});
  EXPECT_EQ(matte.output.find("another render"), std::string::npos) << matte.output;
}

TEST(CliEveryInputProtected, SpecialFilesAreWrittenThroughOrRefusedNeverReplaced) {
  const stdfs::path dir = freshTempDir("protect_special");
  // A report's CSV to /dev/null stays a device; to /dev/full fails with the reason.
  const auto null = runPluvia({"report", "lights", "--quick", "--csv", "/dev/null"});
  EXPECT_EQ(null.exitCode, 0) << null.output;
  struct stat info {};
  ASSERT_EQ(::stat("/dev/null", &info), 0);
  EXPECT_TRUE(S_ISCHR(info.st_mode));
  const auto full = runPluvia({"report", "lights", "--quick", "--csv", "/dev/full"});
  EXPECT_EQ(full.exitCode, 1) << full.output;
  expectOutputHas(full.output, {"/dev/full", "No space left"});

  // A render's frame onto a FIFO is refused before any work.
  const std::string plate = writeTexturedPlate(dir, 1, 1);
  const stdfs::path fifo = dir / "r.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", fifo.string()});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  expectOutputHas(r.output, {"r.png is a FIFO, not a file"});
  EXPECT_TRUE(stdfs::is_fifo(fifo));
}

TEST(CliEveryInputProtected, FifosAreRefusedWhereverAFileIsRead) {
  const stdfs::path dir = freshTempDir("protect_fifo");
  const std::string plate = writeTexturedPlate(dir, 1, 1);
  const stdfs::path fifo = dir / "f.ocio";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const std::string out = (dir / "o.####.png").string();
  const std::vector<std::vector<std::string>> cases{
      {"render", plate, "-p", "drizzle", "-o", out, "--ocio", fifo.string()},
      {"render", plate, "-p", "drizzle", "-o", out, "--set", "depth.source=colmap", "--set",
       "depth.colmap_model=" + dir.string()},
  };
  for (const char* name : {"cameras.txt", "images.txt", "points3D.txt"})
    stdfs::create_symlink(fifo, dir / name);
  for (const std::vector<std::string>& args : cases) {
    // Under `timeout`: reading a FIFO with no writer used to block for ever.
    std::vector<std::string> argv{"timeout", "60", pluviaBinary().string()};
    argv.insert(argv.end(), args.begin(), args.end());
    const ProcessResult r = runProcess(argv);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    expectOutputHas(r.output, {"is a FIFO, not a file"});
  }
}
