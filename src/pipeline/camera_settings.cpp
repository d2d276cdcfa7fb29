#include "pipeline/camera_settings.h"

#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "util/error.h"

namespace pluvia {

namespace {

ParamSpec cameraPathParam() {
  // camera.path: poses over clip frames (geometry/camera_path.h has the angle conventions).
  ParamSpec path = listParam(
      "path", nlohmann::json::array(),
      {{"",
        {required(numberParam("frame", 0.0, {}, "", "clip frame number of this key")),
         required(vectorParam("position_m", {}, "m", "camera position, +Y up")),
         numberParam("yaw_deg", 0.0, {}, "deg", "positive turns right, from -Z toward +X"),
         numberParam("pitch_deg", 0.0, {-90.0, 90.0}, "deg", "positive looks up (= -tilt_deg)"),
         numberParam("roll_deg", 0.0, {-180.0, 180.0}, "deg",
                     "positive: the view's right side goes down")}}},
      "poses over clip frames, interpolated between keys, held outside them; empty: a static "
      "camera from tilt_deg and height_m");
  path.orderedBy = "frame";
  return path;
}

// camera.path items {"frame": F, "position_m": [x, y, z], "yaw_deg": .., "pitch_deg": ..,
// "roll_deg": ..}.
std::vector<std::pair<double, CameraPose>> pathKeys(const nlohmann::json& items) {
  std::vector<std::pair<double, CameraPose>> keys;
  if (!items.is_array()) return keys;
  for (const auto& item : items) {
    CameraPose pose;
    const nlohmann::json& p = item.at("position_m");
    pose.positionMeters = {p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()};
    pose.yawDeg = item.value("yaw_deg", 0.0);
    pose.pitchDeg = item.value("pitch_deg", 0.0);
    pose.rollDeg = item.value("roll_deg", 0.0);
    keys.emplace_back(item.at("frame").get<double>(), pose);
  }
  return keys;
}

}  // namespace

const SettingsTable<CameraSettings>& cameraTable() {
  using S = CameraSettings;
  static const SettingsTable<CameraSettings> table(
      {.name = "camera",
       .help = "The virtual camera that films the rain; match it to the plate's camera."},
      {
          bind(&S::fovDeg,
               numberParam("fov_deg", 36.0, {1.0, 170.0}, "deg", "horizontal field of view")),
          // The exposure may ramp (the rain stage reads it per frame); the rest is fixed for
          // the shot.
          bind(&S::exposureSeconds,
               numberParam("exposure_s", 0.0, {0.0, 1.0}, "s",
                           "shutter time; sets the streak length and brightness; 0: the plate "
                           "camera's: what its files state (ExposureTime, a shutter angle), "
                           "else measured from its motion blur, else the 180-degree shutter "
                           "(half the frame time)")),
          bind(&S::shutterAngleDeg,
               numberParam("shutter_angle_deg", 0.0, {0.0, 360.0}, "deg",
                           "when > 0: exposure = shutter_angle / 360 / fps, overriding "
                           "exposure_s; 0: unused")),
          bind(&S::framesPerSecond,
               numberParam("fps", 0.0, {0.0, 240.0}, "1/s",
                           "frame rate; 0 takes the clip's (24 for sequences)")),
          bind(&S::tiltDeg, numberParam("tilt_deg", 0.0, {-89.0, 89.0}, "deg",
                                        "pitch of the camera, positive looking down")),
          bind(&S::heightMeters, numberParam("height_m", 1.6, {0.0, 1000.0}, "m",
                                             "camera height above the ground plane")),
          bind(&S::focusMeters, numberParam("focus_m", 20.0, {0.0, 1e6}, "m",
                                            "focus distance (the default depth's backdrop); 0: no "
                                            "defocus")),
          bind(&S::fNumber, numberParam("f_number", 11.0, {0.0, 128.0}, "",
                                        "aperture f-number; 0: pinhole, no defocus")),
          bind(&S::sensorWidthMm,
               numberParam("sensor_width_mm", 36.0, {1.0, 100.0}, "mm",
                           "sensor width; with fov_deg gives the focal length (defocus)")),
          bind(&S::lensFromPlate,
               booleanParam("lens_from_plate", true,
                            "where the plate's files state its lens (EXIF or EXR FNumber, "
                            "FocalLength, FocalLengthIn35mmFilm), film the rain through it: "
                            "they replace fov_deg, f_number and sensor_width_mm; false: the "
                            "preset's keys always")),
          unbound<S>(cameraPathParam()),
      });
  return table;
}

CameraSettings cameraSettings(const Preset& p) {
  CameraSettings s = cameraTable().read(p);
  if (p.has("camera.path")) s.pathKeys = pathKeys(p.at("camera.path"));
  // 0 reads the plate's rate; a rate under 1 fps is no video's.
  if (s.framesPerSecond != 0.0 && s.framesPerSecond < 1.0)
    throw Error(fmt::format("camera.fps {:g} is under 1 frame a second: give the plate's rate, "
                            "or 0 to read it from the plate",
                            s.framesPerSecond),
                {"camera"});
  if (s.framesPerSecond > 0.0) s.checkExposureFits(s.framesPerSecond);
  return s;
}

void CameraSettings::checkExposureFits(double fps) const {
  for (const RampKey& key : exposureSeconds.keys())
    if (key.value > 1.0 / fps + 1e-9)
      throw Error(fmt::format("camera.exposure_s {:g} s is longer than a frame at {:g} fps ({:g} "
                              "s): a shutter cannot stay open past the next frame",
                              key.value, fps, 1.0 / fps),
                  {"camera"});
}

Camera CameraSettings::base(int width, int height) const {
  return Camera::fromFieldOfView(width, height, fovDeg, tiltDeg, heightMeters);
}

CameraPath CameraSettings::path(const Camera& base) const {
  if (pathKeys.empty()) return CameraPath::fixed(base);
  return CameraPath::fromKeys(base, pathKeys);
}

double CameraSettings::exposureSecondsAt(double fps, double frame) const {
  if (shutterAngleDeg > 0.0) return shutterAngleDeg / 360.0 / fps;
  const double exposure = exposureSeconds.valueAt(frame);
  return exposure > 0.0 ? exposure : plateShutterSeconds;
}

bool CameraSettings::shutterFromPlate() const {
  if (shutterAngleDeg > 0.0) return false;
  const std::vector<RampKey>& keys = exposureSeconds.keys();
  return std::any_of(keys.begin(), keys.end(), [](const RampKey& k) { return k.value <= 0.0; });
}

double CameraSettings::framesPerSecondOf(double clipFramesPerSecond) const {
  return framesPerSecond > 0.0 ? framesPerSecond : clipFramesPerSecond;
}

}  // namespace pluvia
