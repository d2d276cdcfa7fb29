#pragma once
// The lens the rain is filmed through, where the plate's files state it and camera.lens_from_plate
// is true (every shipped preset): the f-number (EXIF FNumber; an EXR's aperture, which
// OpenImageIO reads as FNumber), the focal length (EXIF FocalLength) and its 35 mm equivalent
// (EXIF FocalLengthIn35mmFilm; a phone movie's focal_length.35mm_equivalent tag). What they state
// replaces the preset's camera.f_number, fov_deg and sensor_width_mm; what they do not stays the
// preset's. Why the plate's: a near drop's blur circle is the lens's entrance pupil (focal
// length over f-number) times its focal length in pixels times (1/d - 1/s) (rain/thin_lens.h):
// focused at 20 m, a phone's 4.3 mm lens at f/2.4 blurs a drop half a metre away over 2.3 px at
// 640 px wide, a 50 mm lens at f/2.8 on a full-frame sensor over 31 px, so only the plate's own
// lens gives its drops' look. The focus distance stays camera.focus_m: it places the guessed
// depth's backdrop too, and a photo's subject distance is not the scene's.
#include <string>

#include "io/clip_reader.h"
#include "pipeline/camera_settings.h"

namespace pluvia {

struct PlateLens {
  double fNumber = 0.0;  // each 0 where the files do not state it
  double focalMm = 0.0;
  double fovDeg = 0.0;  // horizontal, from the 35 mm equivalent over the picture's aspect
  std::string stated;   // what the files state, for the log and the plan; "" when nothing
};

// What the files of `clip` state of its lens, for its picture (the display window where it has
// one, else the frame: the 35 mm equivalent spans the picture's diagonal as 43.27 mm spans
// 36 x 24 mm film's). A field that states no lens (text, 0, out of range) is said and left out.
PlateLens statedLens(const ClipInfo& clip);

// `camera` with what `lens` states put in, where camera.lens_from_plate: the view, the f-number,
// and the sensor width the focal length spans in that view (2 f tan(fov / 2)).
CameraSettings withPlateLens(const CameraSettings& camera, const PlateLens& lens);

// The lens a stage films with and where it comes from, for the log and the plan: "52.6 deg
// view, f/2.4, 4.30 mm focal length on a 4.25 mm-wide sensor: the plate's metadata (...)".
std::string lensLine(const CameraSettings& camera, const PlateLens& lens);

}  // namespace pluvia
