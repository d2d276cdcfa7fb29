#pragma once
// The floors `pluvia bench` measures pluvia against, besides the movie's encoder (issue 31),
// each in the same run as pluvia and each with pluvia run as a user runs it (the whole
// command, process start included, by its wall clock):
// - an EXR sequence in and out against oiiotool reading and writing the same frames;
// - a plate numbered from timecode (86401) against the same frames numbered from 1;
// - the look-dev loop (bench_lookdev.h): a warm look change against the cold render.
#include <filesystem>
#include <string>
#include <vector>

namespace pluvia::cli {

// The bundled example as an image sequence: `frames` frames at 1920x1080 numbered from `first`,
// plate.####.EXTENSION in `folder` (png by ffmpeg; exr as oiiotool converts the PNGs, half
// float, linear). Returns the pattern.
std::string exampleSequence(const std::filesystem::path& folder, int frames, int first,
                            const std::string& extension);

// `pluvia render` of `plate` with `preset` into `output` (a sequence or a movie), quiet: the
// whole command's wall seconds.
double timedRender(const std::string& output, const std::string& plate, const std::string& preset,
                   const std::vector<std::string>& extraArgs);
// An EXR sequence's output pattern in `folder`, for timedRender.
std::string exrOutputIn(const std::filesystem::path& folder);

struct ExrFloor {
  double coldSeconds = 0.0;  // pluvia with a fresh --cache: every per-clip result made
  double warmSeconds = 0.0;  // again with that cache, as a farm's chunks after `prepare`
  double oiiotoolSeconds = 0.0;
  int frames = 0;
};
// 12 frames of 1080p EXR rendered by pluvia, and copied by `oiiotool in -o out` (read, write).
ExrFloor measureExrFloor(const std::filesystem::path& folder, const std::string& preset);

struct TimecodeFloor {
  double fromOneSeconds = 0.0, fromTimecodeSeconds = 0.0;
};
// The same 4 frames numbered from 1 and from 86401, each rendered at --proxy 0.5.
TimecodeFloor measureTimecodeFloor(const std::filesystem::path& folder, const std::string& preset);

}  // namespace pluvia::cli
