// Never lose a frame (issue 16): a full disk, a single-file output for many frames, a truncated
// movie, two renders into one folder, signals, and hostile output names each end in a clear
// error, and every file left under a frame's name is whole.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <functional>
#include <thread>
#include <tuple>

#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

std::string frameName(const std::string& prefix, int frame, const std::string& extension) {
  char name[128];
  std::snprintf(name, sizeof name, "%s.%04d.%s", prefix.c_str(), frame, extension.c_str());
  return name;
}

// Runs pluvia with a file size limit (`ulimit -f`, in the shell's blocks), as a full disk.
CommandResult runPluviaWithFileSizeLimit(const std::string& blocks,
                                         const std::vector<std::string>& args) {
  std::vector<std::string> argv{"sh", "-c",   "ulimit -f \"$1\" && shift && exec \"$@\"",
                                "sh", blocks, pluviaBinary().string()};
  argv.insert(argv.end(), args.begin(), args.end());
  ProcessResult r = runProcess(argv);
  return {r.exitCode, r.output};
}

bool decodes(const stdfs::path& path) {
  try {
    Image image = readImageFile(path);
    return image.width > 0;
  } catch (const std::exception&) {
    return false;
  }
}

int countTemporaries(const stdfs::path& dir) {
  int count = 0;
  for (const auto& e : stdfs::directory_iterator(dir))
    count += e.path().filename().string().find("pluvia-tmp") != std::string::npos;
  return count;
}

// Starts a render of a 2000-frame 64x48 movie (made by ffmpeg as dir/in.mp4: long enough to be
// stopped midway) into dir/out/OUTPUT, logging to dir/log; returns its pid.
pid_t startLongRender(const stdfs::path& dir, const std::string& output) {
  const std::string input = (dir / "in.mp4").string();
  EXPECT_EQ(runProcess({"ffmpeg", "-v", "error", "-f", "lavfi", "-i", "testsrc=size=64x48:rate=24",
                        "-frames:v", "2000", "-c:v", "libx264", "-pix_fmt", "yuv420p", input})
                .exitCode,
            0);
  stdfs::create_directories(dir / "out");
  return startPluvia({"render", input, "-p", "drizzle", "-o", (dir / "out" / output).string()},
                     dir / "log");
}

// Whatever was left in `dir` decodes whole, fewer than `frames` are there, and no temporary is.
void expectOnlyWholeFrames(const stdfs::path& dir, int frames) {
  int whole = 0;
  for (const auto& e : stdfs::directory_iterator(dir)) {
    EXPECT_TRUE(decodes(e.path())) << e.path() << " is left but not a whole image";
    ++whole;
  }
  EXPECT_LT(whole, frames);
  EXPECT_EQ(countTemporaries(dir), 0);
}

}  // namespace

// A file size limit fails every write with EFBIG, as a full disk fails them with ENOSPC.
TEST(CliFrameSafety, FileSizeLimitFailsCleanlyAndResumes) {
  for (const std::string extension : {"png", "jpg"}) {
    SCOPED_TRACE(extension);
    auto dir = freshTempDir("file_size_limit_" + extension);
    auto plate = writeTexturedPlate(dir, 1, 4);
    stdfs::create_directories(dir / "out");
    const std::string out = (dir / "out" / ("o.####." + extension)).string();
    // One block (512 or 1024 bytes): no frame fits.
    auto r = runPluviaWithFileSizeLimit(
        "1", {"render", plate, "-p", "drizzle", "-o", out, "--threads", "1"});
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("File too large"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("wrote 4 frames"), std::string::npos) << r.output;
    expectOnlyWholeFrames(dir / "out", 4);
    r = runPluvia({"render", plate, "-p", "drizzle", "-o", out, "--skip-existing"});
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (int f = 1; f <= 4; ++f) EXPECT_TRUE(decodes(dir / "out" / frameName("o", f, extension)));
  }
}

// A real full disk: a 16 KiB tmpfs holds two of these frames. Needs the right to mount.
TEST(CliFrameSafety, FullDiskFailsAndLeavesOnlyWholeFrames) {
  auto dir = freshTempDir("full_disk");
  auto plate = writeTexturedPlate(dir, 1, 8);
  const stdfs::path disk = dir / "disk";
  stdfs::create_directories(disk);
  if (runProcess({"mount", "-t", "tmpfs", "-o", "size=16k", "tmpfs", disk.string()}).exitCode != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here";
  // Unmounted however the test ends (a failed assertion returns early), lazily so that a file
  // still open cannot keep it mounted.
  struct Unmount {
    stdfs::path disk;
    ~Unmount() { runProcess({"umount", "-l", disk.string()}); }
  } unmount{disk};
  const std::string out = (disk / "o.####.png").string();
  auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", out, "--threads", "1"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("No space left on device"), std::string::npos) << r.output;
  expectOnlyWholeFrames(disk, 8);
}

TEST(CliFrameSafety, SkipExistingRendersEmptyTruncatedAndOtherPresetFramesAgain) {
  auto dir = freshTempDir("skip_checks");
  auto plate = writeTexturedPlate(dir, 1, 4);
  const std::string out = (dir / "o.####.png").string();
  ASSERT_EQ(runPluvia({"render", plate, "-p", "drizzle", "-o", out, "--frames", "1-3"}).exitCode,
            0);
  const std::string whole = fs::readTextFile(dir / "o.0002.png");
  std::ofstream(dir / "o.0001.png", std::ios::binary | std::ios::trunc);  // empty
  std::ofstream(dir / "o.0002.png", std::ios::binary | std::ios::trunc)
      << whole.substr(0, whole.size() / 2);
  auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", out, "--skip-existing"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"1 existing frames skipped", "2 existing frames rendered again",
                             "o.0001.png again: the file is empty"});
  for (int f = 1; f <= 4; ++f) EXPECT_TRUE(decodes(dir / frameName("o", f, "png")));
  // Another seed is another preset: every frame is rendered again.
  r = runPluvia(
      {"render", plate, "-p", "drizzle", "-o", out, "--skip-existing", "--set", "rain.seed=99"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"4 existing frames rendered again", "rendered with preset"});
}

TEST(CliFrameSafety, SkipExistingRendersAnEmptyOrShortMovieAgain) {
  auto dir = freshTempDir("skip_movie");
  auto plate = writeTexturedPlate(dir, 1, 3);
  const std::string movie = (dir / "o.mp4").string();
  std::ofstream(movie, std::ios::binary);  // empty
  auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", movie, "--skip-existing"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("o.mp4 again: the movie is not whole"), std::string::npos) << r.output;
  r = runPluvia({"render", plate, "-p", "drizzle", "-o", movie, "--skip-existing"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("exists, nothing to do"), std::string::npos) << r.output;
  r = runPluvia(
      {"render", plate, "-p", "drizzle", "-o", movie, "--skip-existing", "--frames", "1-2"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("it holds 3 frames, this render makes 2"), std::string::npos) << r.output;
}

TEST(CliFrameSafety, OneImageFileIsRefusedForManyFramesAndTakesOne) {
  auto dir = freshTempDir("single_file");
  auto plate = writeTexturedPlate(dir, 1, 3);
  const std::string out = (dir / "still.exr").string();
  auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", out});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("is one image file, but 3 frames"), std::string::npos) << r.output;
  EXPECT_FALSE(stdfs::exists(out));
  r = runPluvia({"render", plate, "-p", "drizzle", "-o", out, "--frames", "2-2"});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(decodes(out));
}

TEST(CliFrameSafety, APresetOverTheArgumentLimitStillMakesMoviesAndSmallFrames) {
  auto dir = freshTempDir("large_preset");
  auto plate = writeTexturedPlate(dir, 1, 2);
  const std::string preset = (dir / "large.json").string();
  std::ofstream(preset) << R"({"pluvia": 1, "extends": "drizzle", "description": ")"
                        << std::string(200 * 1024, 'x') << "\"}";
  auto r = runPluvia({"render", plate, "-p", preset, "-o", (dir / "o.mp4").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output.substr(0, 2000);
  EXPECT_GT(stdfs::file_size(dir / "o.mp4"), 1000u);
  r = runPluvia({"render", plate, "-p", preset, "-o", (dir / "o.####.exr").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output.substr(0, 2000);
  EXPECT_LT(stdfs::file_size(dir / "o.0001.exr"), 64u * 1024);
  auto info = runProcess({"oiiotool", "--info", "-v", (dir / "o.0001.exr").string()});
  expectOutputHas(info.output, {"pluvia:presetHash", "not copied"});
}

TEST(CliFrameSafety, ATruncatedMovieIsAnErrorNamingTheFirstMissingFrame) {
  auto dir = freshTempDir("truncated_movie");
  const std::string whole = (dir / "whole.mp4").string();
  ASSERT_EQ(runProcess({"ffmpeg", "-v", "error", "-f", "lavfi", "-i", "testsrc=size=64x48:rate=24",
                        "-frames:v", "48", "-c:v", "libx264", "-pix_fmt", "yuv420p", "-movflags",
                        "+faststart", whole})
                .exitCode,
            0);
  const std::string bytes = fs::readTextFile(whole);
  std::ofstream(dir / "cut.mp4", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  auto r = runPluvia(
      {"render", (dir / "cut.mp4").string(), "-p", "drizzle", "-o", (dir / "o.####.png").string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(
      r.output.find("cut.mp4 is truncated or corrupt: its container lists 48 frames, but frame"),
      std::string::npos)
      << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "o.0000.png"));
  // The whole movie still renders.
  r = runPluvia(
      {"render", whole, "-p", "drizzle", "-o", (dir / "w.####.png").string(), "--frames", "0-1"});
  EXPECT_EQ(r.exitCode, 0) << r.output;
}

TEST(CliFrameSafety, ASecondRenderIntoTheSameFramesIsRefusedNamingTheFirst) {
  auto dir = freshTempDir("output_lock");
  auto plate = writeTexturedPlate(dir, 1, 2);
  const std::string lockPath = (dir / "o.####.png.pluvia-lock").string();
  // A render in progress: its lock file, held whole (as a movie's render holds it).
  std::ofstream(lockPath) << "4242 farm-node-7\n";
  const int fd = ::open(lockPath.c_str(), O_RDWR | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  struct flock whole {};
  whole.l_type = F_WRLCK;
  whole.l_whence = SEEK_SET;
  ASSERT_EQ(fcntl(fd, F_OFD_SETLK, &whole), 0);
  auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", (dir / "o.%04d.png").string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("another render (pid and host: 4242 farm-node-7)"), std::string::npos)
      << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
  // Once that render is gone (its process dead: the kernel drops the lock), the file left
  // behind holds nothing: the next render takes it and removes it when done.
  ::close(fd);
  r = runPluvia({"render", plate, "-p", "drizzle", "-o", (dir / "o.####.png").string()});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(decodes(dir / "o.0002.png"));
  EXPECT_FALSE(stdfs::exists(lockPath));
}

TEST(CliFrameSafety, ChunksOfOneOutputRenderTogetherAndAnOverlapIsRefused) {
  auto dir = freshTempDir("output_lock_chunks");
  auto plate = writeTexturedPlate(dir, 1, 4);
  const std::string lockPath = (dir / "o.####.png.pluvia-lock").string();
  // A farm chunk rendering frames 3-4 (on another host, say): its bytes of the lock file
  // (64 per frame), with its pid and host at their start, and a temporary of its frame 3.
  const int fd = ::open(lockPath.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(pwrite(fd, "4242 farm-node-7\n", 17, 3 * 64), 17);
  struct flock frames3to4 {};
  frames3to4.l_type = F_WRLCK;
  frames3to4.l_whence = SEEK_SET;
  frames3to4.l_start = 3 * 64;
  frames3to4.l_len = 2 * 64;
  ASSERT_EQ(fcntl(fd, F_OFD_SETLK, &frames3to4), 0);
  // Pid 999999 runs no process here; one temporary is the other chunk's, one a killed render's.
  std::ofstream(dir / "o.0003.pluvia-tmp-999999-0.png") << "half a frame";
  std::ofstream(dir / "o.0001.pluvia-tmp-999999-1.png") << "half a frame";

  auto overlap = runPluvia(
      {"render", plate, "-p", "drizzle", "-o", (dir / "o.####.png").string(), "--frames", "2-3"});
  EXPECT_EQ(overlap.exitCode, 1) << overlap.output;
  EXPECT_NE(overlap.output.find("another render (pid and host: 4242 farm-node-7) is writing "
                                "frames 3-4 of "),
            std::string::npos)
      << overlap.output;
  EXPECT_FALSE(stdfs::exists(dir / "o.0002.png"));

  auto chunk = runPluvia(
      {"render", plate, "-p", "drizzle", "-o", (dir / "o.####.png").string(), "--frames", "1-2"});
  EXPECT_EQ(chunk.exitCode, 0) << chunk.output;
  EXPECT_TRUE(decodes(dir / "o.0001.png"));
  EXPECT_TRUE(decodes(dir / "o.0002.png"));
  // Its own frames' temporary is removed; the other chunk's is not, though its pid runs nothing
  // here; and the lock file stays for the other chunk.
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.pluvia-tmp-999999-1.png"));
  EXPECT_TRUE(stdfs::exists(dir / "o.0003.pluvia-tmp-999999-0.png"));
  EXPECT_TRUE(stdfs::exists(lockPath));
  ::close(fd);
}

// SIGTERM, and SIGHUP (a closed terminal or ssh session: it left the temporary movie, its
// ffmpeg log and the lock, adversarial S23), stop a movie render cleanly.
TEST(CliFrameSafety, SigtermAndSighupStopAMovieRenderAndRemoveItsPartialFile) {
  for (const auto& [signal, name, code] :
       {std::tuple{SIGTERM, "SIGTERM", 143}, std::tuple{SIGHUP, "SIGHUP", 129}}) {
    SCOPED_TRACE(name);
    auto dir = freshTempDir(std::string("stop_movie_") + name);
    const pid_t pid = startLongRender(dir, "o.mp4");
    // Stopped once the encoder has written part of the movie.
    EXPECT_TRUE(waitUntil([&] { return countTemporaries(dir / "out") > 0; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    kill(pid, signal);
    EXPECT_EQ(waitForExit(pid), code) << fs::readTextFile(dir / "log");
    EXPECT_NE(fs::readTextFile(dir / "log").find(std::string("stopped by ") + name),
              std::string::npos);
    EXPECT_TRUE(stdfs::is_empty(dir / "out")) << "a partial movie, temporary or lock is left";
  }
}

// A second signal, sent before the render has stopped for the first, stopped it with the default
// action: its temporary movie, the encoder's log beside it and the lock were left. The second
// now stops it at once and leaves nothing either.
TEST(CliFrameSafety, ASecondSignalStopsAtOnceAndLeavesNothing) {
  for (const int gapMs : {2, 20}) {
    SCOPED_TRACE(gapMs);
    auto dir = freshTempDir("stop_twice_" + std::to_string(gapMs));
    const pid_t pid = startLongRender(dir, "o.mp4");
    EXPECT_TRUE(waitUntil([&] { return countTemporaries(dir / "out") > 0; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    kill(pid, SIGTERM);
    std::this_thread::sleep_for(std::chrono::milliseconds(gapMs));
    kill(pid, SIGTERM);
    // 143 from the handler, or killed by the second SIGTERM after the render had cleaned up and
    // given the signal its default action back: either way a farm sees SIGTERM.
    const int code = waitForExit(pid);
    EXPECT_TRUE(code == 143 || code == 1000 + SIGTERM) << code << fs::readTextFile(dir / "log");
    // The encoder, which outlives a hard stop by a moment, writes into the removed file.
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    std::vector<std::string> left;
    for (const auto& e : stdfs::directory_iterator(dir / "out"))
      left.push_back(e.path().filename().string());
    EXPECT_TRUE(left.empty()) << "left: " << testing::PrintToString(left) << " exit " << code;
  }
}

// Piped into a reader that stops early (`render ... 2>&1 | head -c 3000`), the render died of
// SIGPIPE at its next message with its lock held. It now goes on to its end.
TEST(CliFrameSafety, AReaderThatStopsEarlyLeavesNoLock) {
  auto dir = freshTempDir("sigpipe");
  const std::string plate = writeTexturedPlate(dir, 1, 6);
  stdfs::create_directories(dir / "out");
  const ProcessResult r =
      runProcess({"sh", "-c", "\"$0\" render \"$1\" -p moderate -o \"$2\" 2>&1 | head -c 10",
                  pluviaBinary().string(), plate, (dir / "out" / "o.####.png").string()});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  std::vector<std::string> left;
  for (const auto& e : stdfs::directory_iterator(dir / "out"))
    left.push_back(e.path().filename().string());
  EXPECT_EQ(left.size(), 6u) << testing::PrintToString(left);
  for (const std::string& name : left)
    EXPECT_EQ(name.find("pluvia-lock"), std::string::npos) << name;
}

// A derain killed mid-write left a temporary that no rerun removed (S23).
TEST(CliFrameSafety, DerainRemovesTheTemporariesOfAKilledDerain) {
  auto dir = freshTempDir("derain_stale");
  auto plate = writeTexturedPlate(dir, 1, 6);
  stdfs::create_directories(dir / "d");
  // pid 999999 runs no process (pid_max is 4194304 at most, and this one is not started).
  const stdfs::path stale = dir / "d" / "c.0001.pluvia-tmp-999999-0.png";
  std::ofstream(stale) << "half a frame";
  const auto r = runPluvia({"derain", plate, "-o", (dir / "d" / "c.####.png").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_FALSE(stdfs::exists(stale));
  EXPECT_EQ(countTemporaries(dir / "d"), 0);
}

TEST(CliFrameSafety, SigintStopsASequenceRenderLeavingWholeFramesOnly) {
  auto dir = freshTempDir("sigint_sequence");
  const pid_t pid = startLongRender(dir, "o.####.png");
  EXPECT_TRUE(waitUntil([&] { return stdfs::exists(dir / "out" / "o.0003.png"); }));
  kill(pid, SIGINT);
  EXPECT_EQ(waitForExit(pid), 130) << fs::readTextFile(dir / "log");
  expectOnlyWholeFrames(dir / "out", 2000);
}

TEST(CliFrameSafety, ARenderRemovesItsOutputsTemporariesOfDeadRendersOnly) {
  auto dir = freshTempDir("stale_temporaries");
  auto plate = writeTexturedPlate(dir, 1, 1);
  stdfs::create_directories(dir / "out");
  // A pid that runs no process (the highest free one below pid_max: pids are handed out upwards,
  // but after a wrap on a busy machine pid_max - 1 can be taken), and our own.
  int deadPid = 4194303;
  std::ifstream("/proc/sys/kernel/pid_max") >> deadPid;
  do --deadPid;
  while (deadPid > 300 && stdfs::exists("/proc/" + std::to_string(deadPid)));
  ASSERT_FALSE(stdfs::exists("/proc/" + std::to_string(deadPid)));
  const stdfs::path dead =
      dir / "out" / ("o.0001.pluvia-tmp-" + std::to_string(deadPid) + "-0.png");
  const stdfs::path deadAov =
      dir / "out" / ("o.rain.0001.pluvia-tmp-" + std::to_string(deadPid) + "-1.png");
  const stdfs::path live =
      dir / "out" / ("o.0001.pluvia-tmp-" + std::to_string(getpid()) + "-0.png");
  // Another output's: its own render cleans it.
  const stdfs::path otherOutput =
      dir / "out" / ("m.pluvia-tmp-" + std::to_string(deadPid) + "-2.mp4.log");
  for (const auto& path : {dead, deadAov, live, otherOutput}) std::ofstream(path) << "partial";
  auto r =
      runPluvia({"render", plate, "-p", "drizzle", "-o", (dir / "out" / "o.####.png").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("removed 2 temporary files"), std::string::npos) << r.output;
  EXPECT_FALSE(stdfs::exists(dead));
  EXPECT_FALSE(stdfs::exists(deadAov));
  EXPECT_TRUE(stdfs::exists(live));
  EXPECT_TRUE(stdfs::exists(otherOutput));
}

TEST(CliFrameSafety, DevicesAreRefusedAsInputs) {
  auto dir = freshTempDir("device_inputs");
  auto plate = writeTexturedPlate(dir, 1, 1);
  const std::string out = (dir / "o.####.png").string();
  const std::vector<std::vector<std::string>> cases{
      {plate, "--set", "lighting.source=hdr", "--set", "lighting.hdr=/dev/zero"},
      {plate, "--set", "rain.strokes=derain", "--set", "derain.input=/dev/zero"},
      {"/dev/zero"}};
  for (const std::vector<std::string>& inputAndSets : cases) {
    // Under `timeout`: reading /dev/zero used to spin forever.
    std::vector<std::string> argv{
        "timeout", "60", pluviaBinary().string(), "render", "-p", "drizzle", "-o", out};
    argv.insert(argv.end(), inputAndSets.begin(), inputAndSets.end());
    const ProcessResult r = runProcess(argv);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    expectOutputHas(r.output, {"/dev/zero", "not a regular file"});
  }
}

TEST(CliFrameSafety, MovieNamesThatLookLikeOptionsOrProtocolsAreFiles) {
  auto dir = freshTempDir("movie_names");
  auto plate = writeTexturedPlate(dir, 1, 2);
  for (const std::string name : {"-y.mp4", "pipe:1.mp4"}) {
    const ProcessResult r =
        runProcess({"sh", "-c", "cd \"$1\" && shift && exec \"$@\"", "sh", dir.string(),
                    pluviaBinary().string(), "render", plate, "-p", "drizzle", "--output=" + name});
    EXPECT_EQ(r.exitCode, 0) << name << "\n" << r.output;
    EXPECT_GT(stdfs::file_size(dir / name), 1000u) << name;
  }
}

// No date and no command line in the frames: a frame's file is the same bytes whether it was
// rendered alone or in a chunk, at whatever time, into whatever folder.
TEST(CliFrameSafety, ChunkedFramesAreByteIdenticalFiles) {
  auto dir = freshTempDir("byte_identical");
  auto plate = writeTexturedPlate(dir, 1, 3);
  const std::vector<std::string> extensions{"exr", "tif", "dpx", "png", "jpg"};
  auto render = [&](const std::string& folder, const std::string& extension,
                    const std::vector<std::string>& extra) {
    std::vector<std::string> args{
        "render", plate, "-p", "drizzle", "-o", (dir / folder / ("o.####." + extension)).string()};
    args.insert(args.end(), extra.begin(), extra.end());
    auto r = runPluvia(args);
    EXPECT_EQ(r.exitCode, 0) << r.output;
  };
  for (const std::string& extension : extensions) render("chunk", extension, {"--frames", "1-3"});
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // another second on the clock
  for (const std::string& extension : extensions)
    render("alone", extension, {"--frames", "2-2", "--threads", "1"});
  for (const std::string& extension : extensions) {
    const std::string frame = frameName("o", 2, extension);
    EXPECT_TRUE(fs::readTextFile(dir / "chunk" / frame) == fs::readTextFile(dir / "alone" / frame))
        << extension << " frames differ";
  }
}
