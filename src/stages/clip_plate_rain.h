#pragma once
// Whether the clip was shot in rain (derain/plate_rain.h), measured once per clip on first use
// on 9 consecutive frames from its middle (the same for every chunk of a farm render; a proxy's
// at the size they were filmed at), with its streaks' length and width (the shutter's clock on a
// rained plate: stages/plate_shutter.h), and what
// the grading stages (darken, blur, fog) do with it: a plate shot in rain already holds the veil
// they would add, so each leaves itself out there unless its `over_rain` asks for it.
#include <string>

#include "pipeline/stage.h"
#include "preset/param_table.h"

namespace pluvia {

// clip.plateRain, measured on first use (or taken from the check started ahead). A clip of
// fewer than 3 frames (or none: a stage run on its own) is taken as dry.
const PlateRainFinding& clipPlateRain(ClipContext& clip);

// Starts the check on a thread and a reader of its own (clip.openWorkingReader), for a stage's
// prepareAhead(): it reads and measures its 9 frames beside the lighting's and depth's analyses
// instead of after them. Nothing to start with one thread, without that reader, or when the
// finding is known (cached, or started already).
void startPlateRainCheck(ClipContext& clip);

// True, with a log line naming `stage`, when the stage is to leave the clip as it is: not
// `overRain` and the plate was shot in rain.
bool leaveOutOnRainedPlate(ClipContext& clip, const std::string& stage, bool overRain);

// The plan's note for a grading stage: what it does on a plate shot in rain.
std::string rainedPlateNote(const std::string& stage, bool overRain);

// For the plan (StageInfo::cachedWork of a grading stage): "the plate's rain check from the
// cache" when `cache` holds it for the clip's frames (`framesKey`: render_job.h's
// workingFramesKey) and the stage needs it (not `overRain`), else "".
std::string cachedPlateRainNote(const ClipInfo& clip, const std::string& framesKey,
                                const ArtifactCache& cache, bool overRain);

// The over_rain key every grading stage has.
ParamSpec overRainParam();

}  // namespace pluvia
