// `pluvia prepare` fills the cache once for every chunk of a render; two prepares at once
// compute each entry once; `render --require-cache` refuses a cache that lacks an entry.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "test_support.h"
#include "util/fs.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

std::string plate(const stdfs::path& dir) {
  // A bright sky over a dark ground, so that the plate's lighting has something to measure.
  constexpr int kWidth = 64, kHeight = 48;
  return writePixelPlate(dir, 1, 6, kWidth, kHeight, [](float* p, int x, int y, int frame) {
    const float v = y < kHeight / 2 ? 0.9f : 0.1f + 0.01f * float((x + frame) % 7);
    p[0] = p[1] = p[2] = v;
  });
}

// The lighting entry's file name, as `pluvia prepare` prints it ("computed lighting PATH").
std::string lightingEntryName(const std::string& output) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    const size_t at = line.find("lighting ");
    if (at == std::string::npos || line.find(".json") == std::string::npos) continue;
    std::string path = line.substr(line.find_first_not_of(' ', at + 9));
    return stdfs::path(path).filename().string();
  }
  return "";
}

// A background process's log so far ("" before the process has created it).
std::string readLog(const stdfs::path& path) {
  return stdfs::exists(path) ? fs::readTextFile(path) : "";
}

int countOf(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(CliPrepare, FillsTheCacheSoThatARenderWithRequireCacheOnlyReadsIt) {
  const auto dir = freshTempDir("prepare_fill");
  const std::string input = plate(dir);
  const std::string cache = (dir / "cache").string();
  const std::string out = (dir / "out" / "o.####.png").string();
  // Before prepare: refused before any frame, naming the missing entry and what to run.
  auto refused = runPluvia({"render", input, "-p", "drizzle", "--cache", cache, "--require-cache",
                            "-o", out, "--frames", "1-2"});
  EXPECT_EQ(refused.exitCode, 1) << refused.output;
  EXPECT_NE(refused.output.find("--require-cache: the per-clip analysis of " + input +
                                " is not in " + cache + ": lighting ("),
            std::string::npos)
      << refused.output;
  EXPECT_NE(refused.output.find("run `pluvia prepare`"), std::string::npos);
  EXPECT_FALSE(stdfs::exists(dir / "out" / "o.0001.png"));

  auto prepared = runPluvia({"prepare", input, "-p", "drizzle", "--cache", cache});
  ASSERT_EQ(prepared.exitCode, 0) << prepared.output;
  const std::string entry = lightingEntryName(prepared.output);
  ASSERT_FALSE(entry.empty()) << prepared.output;
  EXPECT_NE(prepared.output.find("added     lighting"), std::string::npos) << prepared.output;
  EXPECT_TRUE(stdfs::exists(stdfs::path(cache) / entry));
  // A second prepare finds it there.
  auto again = runPluvia({"prepare", input, "-p", "drizzle", "--cache", cache});
  EXPECT_NE(again.output.find("cached    lighting"), std::string::npos) << again.output;

  auto render = runPluvia({"render", input, "-p", "drizzle", "--cache", cache, "--require-cache",
                           "-o", out, "--frames", "1-2", "-v"});
  ASSERT_EQ(render.exitCode, 0) << render.output;
  // The per-clip work without an entry of its own stage came from the prepare too: the chunk
  // made none of it.
  expectOutputHas(render.output, {"lighting: from the plate, from cache",
                                  "still: the median of the clip's frames, from cache",
                                  "sky: found in the still, from cache"});
  EXPECT_EQ(render.output.find("still: the median of 5 frames in"), std::string::npos)
      << render.output;
  EXPECT_TRUE(stdfs::exists(dir / "out" / "o.0002.png"));
  // --require-cache without a cache is a usage error.
  EXPECT_EQ(runPluvia({"render", input, "-p", "drizzle", "--require-cache", "-o", out}).exitCode,
            2);
}

TEST(CliPrepare, TwoPreparesAtOnceComputeTheEntryOnce) {
  const auto dir = freshTempDir("prepare_two");
  const std::string input = plate(dir);
  // The entry's name (its key does not depend on the cache folder), from a prepare elsewhere.
  auto probe = runPluvia({"prepare", input, "-p", "drizzle", "--cache", (dir / "probe").string()});
  ASSERT_EQ(probe.exitCode, 0) << probe.output;
  const std::string entry = lightingEntryName(probe.output);
  ASSERT_FALSE(entry.empty()) << probe.output;

  // This test holds the entry's lock, as a process computing it would, until both prepares are
  // waiting for it: they then race for it, and the loser must read what the winner stored.
  const stdfs::path cache = dir / "cache";
  stdfs::create_directories(cache);
  const std::string lockPath = (cache / (entry + ".pluvia-lock")).string();
  const int fd = ::open(lockPath.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(pwrite(fd, "4242 farm-node-7\n", 17, 0), 17);
  struct flock whole {};
  whole.l_type = F_WRLCK;
  whole.l_whence = SEEK_SET;
  ASSERT_EQ(fcntl(fd, F_OFD_SETLK, &whole), 0);
  const std::vector<std::string> args{"prepare", input, "-p", "drizzle", "--cache", cache.string()};
  const int a = startPluvia(args, dir / "a.log");
  const int b = startPluvia(args, dir / "b.log");
  const std::string waiting =
      "lighting: waiting for the process computing this clip's analysis (pid and host: 4242 "
      "farm-node-7; lock file " +
      lockPath + ")";
  EXPECT_TRUE(waitUntil([&] {
    return readLog(dir / "a.log").find(waiting) != std::string::npos &&
           readLog(dir / "b.log").find(waiting) != std::string::npos;
  })) << readLog(dir / "a.log")
      << readLog(dir / "b.log");
  ::close(fd);  // the holder is done, having stored nothing
  EXPECT_EQ(waitForExit(a), 0) << readLog(dir / "a.log");
  EXPECT_EQ(waitForExit(b), 0) << readLog(dir / "b.log");
  const std::string logs = readLog(dir / "a.log") + readLog(dir / "b.log");
  EXPECT_EQ(countOf(logs, "lighting: from the plate, above"), 1) << logs;  // computed once
  EXPECT_EQ(countOf(logs, "lighting: from the plate, from cache"), 1) << logs;
  EXPECT_TRUE(stdfs::exists(cache / entry));
  EXPECT_EQ(fs::readTextFile(cache / entry), fs::readTextFile(dir / "probe" / entry));
  EXPECT_FALSE(stdfs::exists(lockPath)) << "the last holder removes the lock file";
}
