#pragma once
// `pluvia bench --lookdev`: the look-development loop as an artist meets it. One frame is
// rendered at proxy 0.5 with a fresh --cache (cold: every per-clip result made), then again
// after each of a few --set changes that touch only per-frame stages (warm: the per-clip
// results read from the cache). Each is the whole `pluvia render` command, process start
// included, timed by its wall clock.
#include <string>

namespace pluvia::cli {

struct LookdevTimes {
  double coldSeconds = 0.0;
  double warmSeconds = 0.0;  // the median over the look changes
};

// Prints the table and returns its times. `input` empty: a 1080p PNG sequence made from the
// bundled example (24 frames, numbered from 1001), the form a facility's plates come in.
LookdevTimes runLookdevBench(const std::string& input, const std::string& preset);

}  // namespace pluvia::cli
