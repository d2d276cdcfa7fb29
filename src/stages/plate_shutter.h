#pragma once
// The shutter the rain is filmed with when the preset leaves it to the plate (camera.exposure_s 0
// and no camera.shutter_angle_deg): the streaks' length and light are set by the shutter alone,
// so it is the plate camera's own. In this order:
//   1. what the plate's files state: ExposureTime (EXIF, EXR expTime), else a shutter angle at
//      the clip's frame rate (ShutterAngle: an EXR attribute or a movie's tag);
//   2. measured from the plate's own motion blur (derain/motion_blur.h) on 7 frames from the
//      clip's middle; where the blur is too short to see, the longest shutter that agrees with
//      it (an upper bound);
//   3. the 180-degree shutter at the clip's frame rate (half the frame time), what cinema plates
//      are filmed at, when neither says more (a still without EXIF, a plate where nothing moves).
// A plate shot in rain (stages/clip_plate_rain.h) holds a better clock than a bound or that
// guess: its own streaks (derain::shutterFromStreaksSeconds); shorter than the bound or the
// guess, it is taken.
#include <functional>
#include <optional>
#include <string>

#include "pipeline/camera_settings.h"
#include "pipeline/stage.h"

namespace pluvia {

// Step 1 alone: the shutter the files of `clip` state at `fps`, or none.
std::optional<PlateShutter> statedShutter(const ClipInfo& clip, double fps);

// Steps 1 to 3 for a clip at `fps` whose frames `read` gives in the working space (linear). The
// measurement is cached in `cache` under `framesKey` (render_job.h's workingFramesKey) when both
// are given.
PlateShutter findPlateShutter(const ClipInfo& clip, double fps,
                              const std::function<Image(int64_t)>& read,
                              ArtifactCache* cache = nullptr, const std::string& framesKey = "");

// clip.plateShutter, found on first use: findPlateShutter, refined by the plate's own rain
// where that finding is not firm and the plate was shot in rain.
const PlateShutter& clipPlateShutter(ClipContext& clip);

// How blurred the plate's still edges are (its lens, sensor and codec): the sigma of their
// Gaussian, px at the size rendered, measured with its motion blur (derain::ShutterFromBlur::
// stillBlurPx); 0 for a clip of fewer than 3 frames or too few still edges. Found once per clip.
double clipPlateStillBlurPx(ClipContext& clip);

// Sets camera.plateShutterSeconds from clipPlateShutter when the camera takes the plate's
// shutter, and logs the shutter the stage films with and where it comes from.
void resolvePlateShutter(CameraSettings& camera, ClipContext& clip, const char* stage);

// What the preset says of the shutter, for the log and the plan: "the preset's
// camera.shutter_angle_deg 180 at 24 fps", or "" when it leaves it to the plate.
std::string presetShutterSource(const CameraSettings& camera, double fps);

}  // namespace pluvia
