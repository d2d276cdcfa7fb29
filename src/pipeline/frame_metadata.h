#pragma once
// What every rendered frame (and movie) records about how it was made.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "pipeline/stage.h"
#include "preset/preset.h"

namespace pluvia {

// Past this the resolved preset is not copied into frames: a preset with a 50 MB description
// made 52 MB frames, and a movie's metadata goes to ffmpeg as one argument, which the kernel
// caps at 128 KiB. The shipped presets resolve to about 6 KB.
inline constexpr size_t kMaxPresetMetadataBytes = 16 * 1024;

// "pluvia:version", "pluvia:presetHash", "pluvia:preset" (the resolved preset as JSON, or a note
// that it was too large to copy; the hash names it either way) and what each of `stages` adds
// (StageInfo::frameMetadata: the rain's "pluvia:seed"). Nothing that changes from run to run (no
// command line, no date), so a frame's file is byte-identical whether it was rendered alone, in a
// chunk or in a full run.
std::map<std::string, std::string> frameMetadata(const Preset& preset,
                                                 const std::vector<StageInfo>& stages);

}  // namespace pluvia
