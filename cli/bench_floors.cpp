#include "bench_floors.h"

#include <chrono>
#include <vector>

#include <fmt/format.h>

#include "common.h"
#include "util/error.h"
#include "util/executable.h"
#include "util/subprocess.h"
#include "util/timer.h"

namespace pluvia::cli {
namespace stdfs = std::filesystem;

namespace {

void run(const std::vector<std::string>& command, const std::string& what) {
  const auto r = runProcess(command);
  if (r.exitCode != 0) throw Error(fmt::format("bench: {} failed: {}", what, r.output));
}

}  // namespace

std::string exampleSequence(const stdfs::path& folder, int frames, int first,
                            const std::string& extension) {
  const std::string example = findBesideInstall("examples/street/street_plate.mp4");
  if (example.empty())
    throw UsageError(
        "bench: the bundled example examples/street/street_plate.mp4 is neither beside the "
        "install prefix nor in the current directory");
  stdfs::create_directories(folder);
  const std::string png = (folder / "plate.%04d.png").string();
  run({"ffmpeg", "-y", "-v", "error", "-i", example, "-frames:v", std::to_string(frames), "-vf",
       "scale=1920:1080", "-start_number", std::to_string(first), png},
      "ffmpeg making a 1080p sequence of the example");
  if (extension == "png") return (folder / "plate.####.png").string();
  const std::string range = fmt::format("{}-{}", first, first + frames - 1);
  run({"oiiotool", "--frames", range, (folder / "plate.#.png").string(), "--colorconvert", "sRGB",
       "linear", "-d", "half", "-o", (folder / "plate.#.exr").string()},
      "oiiotool converting the sequence to EXR");
  return (folder / "plate.####.exr").string();
}

double timedRender(const std::string& output, const std::string& plate, const std::string& preset,
                   const std::vector<std::string>& extraArgs) {
  std::vector<std::string> command = {
      executablePath().string(), "render", plate, "-p", preset, "-q", "-o", output};
  command.insert(command.end(), extraArgs.begin(), extraArgs.end());
  const auto started = std::chrono::steady_clock::now();
  run(command, "pluvia render " + plate);
  return secondsSince(started);
}

std::string exrOutputIn(const stdfs::path& folder) {
  return (folder / "out.####.exr").string();
}

ExrFloor measureExrFloor(const stdfs::path& folder, const std::string& preset) {
  ExrFloor floor;
  floor.frames = 12;
  const stdfs::path in = folder / "exr_in", copy = folder / "exr_oiiotool";
  const std::string plate = exampleSequence(in, floor.frames, 1001, "exr");
  stdfs::create_directories(copy);
  const auto started = std::chrono::steady_clock::now();
  run({"oiiotool", "--frames", fmt::format("1001-{}", 1000 + floor.frames),
       (in / "plate.#.exr").string(), "-o", (copy / "plate.#.exr").string()},
      "oiiotool copying the EXR sequence");
  floor.oiiotoolSeconds = secondsSince(started);
  const std::vector<std::string> cache = {"--cache", (folder / "cache").string()};
  for (double* seconds : {&floor.coldSeconds, &floor.warmSeconds}) {
    const stdfs::path out = folder / (seconds == &floor.coldSeconds ? "cold" : "warm");
    stdfs::create_directories(out);
    *seconds = timedRender(exrOutputIn(out), plate, preset, cache);
  }
  return floor;
}

TimecodeFloor measureTimecodeFloor(const stdfs::path& folder, const std::string& preset) {
  TimecodeFloor floor;
  const std::vector<std::string> proxy = {"--proxy", "0.5"};
  const stdfs::path one = folder / "numbered_from_1", timecode = folder / "numbered_from_86401";
  const std::string fromOne = exampleSequence(one, 4, 1, "png");
  const std::string fromTimecode = exampleSequence(timecode, 4, 86401, "png");
  floor.fromOneSeconds = timedRender(exrOutputIn(one), fromOne, preset, proxy);
  floor.fromTimecodeSeconds = timedRender(exrOutputIn(timecode), fromTimecode, preset, proxy);
  return floor;
}

}  // namespace pluvia::cli
