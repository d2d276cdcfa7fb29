#pragma once
// What ffprobe says about a movie's first video stream, and the frames pluvia reads from it:
// its nominal rate, how many frames that rate gives, whether the timing is variable, and how
// many bits its samples carry.
#include <cstdint>
#include <map>
#include <string>

namespace pluvia {

struct MovieProbe {
  int width = 0;  // as decoded (a 90-degree rotation applied)
  int height = 0;
  std::string pixelFormat;  // ffmpeg's name: "yuv420p", "yuv444p12le"
  int bitsPerSample = 8;    // of the decoded samples: 8, 10, 12, 16
  std::string rate;         // nominal rate as ffmpeg writes it: "24000/1001"
  double fps = 0;
  int64_t frames = 0;   // at the nominal rate (a variable-rate movie: its duration's worth)
  int64_t packets = 0;  // coded frames in the stream
  bool variableRate = false;
  // Input metadata for the output, in OpenImageIO's names: "smpte:TimeCode" ("01:00:00:00"),
  // "Make", "Model", and the stream's colour tags as "ffmpeg:color_primaries" and so on.
  std::map<std::string, std::string> metadata;
};

// Runs ffprobe (demuxing the stream once to list its packets). Throws pluvia::Error naming the
// file when ffprobe is missing, fails, or finds no video stream, and when the timing is variable
// and no nominal rate (at most 240 fps) is known to conform it to.
MovieProbe probeMovie(const std::string& path);

}  // namespace pluvia
