#pragma once
// Environment maps from footage (Wang et al. section 4.1): the frames of a panning shot placed
// in an equirect environment at the angles the camera saw them from, unseen directions filled
// with the nearest seen colour, saturated light sources given their measured radiance.
// Conventions: image/equirect.h (the image centre looks along -Z, +Y up); a frame's camera looks
// along its own -Z with +X right and +Y up in the image; `cameraToWorld` rotates camera
// directions into the environment. Frame 0 of a placement looks along world -Z, level.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "image/equirect.h"

namespace pluvia::envmap {

// One frame to place: scene-linear RGB (CV_32FC3, R G B order), and a mask of its saturated
// pixels (CV_8UC1, nonzero where any channel of the source clipped; may be empty).
struct PanoramaFrame {
  cv::Mat linearRgb;
  cv::Mat saturated;
};

struct CameraPose {
  cv::Matx33d cameraToWorld = cv::Matx33d::eye();
  double focalPx = 0.0;  // pinhole focal length in pixels; principal point at the image centre
};

struct Placement {
  std::vector<CameraPose> poses;  // one per frame
  bool fromFeatures = false;      // false: the fallback (field of view and assumed motion)
  std::string note;               // why the fallback was taken, or which frames were placed how
  std::vector<int> interpolated;  // frames with too few features, placed between neighbours
};

struct PlacementSettings {
  double horizontalFovDeg = 36.0;  // used for the fallback, and to seed the focal estimate
  // Fallback motion: yaw per frame in degrees (positive turns right); 0 places every frame at
  // the same angle (static or looming camera).
  double fallbackYawPerFrameDeg = 0.0;
};

// Camera poses from OpenCV's stitching pipeline (features, pairwise matching, rotation-only
// camera model with bundle adjustment) on the frames that have features; frames with too few
// (sky, fog, a blank wall, a flash) are placed between their neighbours and listed. Falls back
// to the field of view and the assumed yaw when fewer than half the frames have features or
// they do not match, saying why in `note`; never throws for that. A single frame is placed
// looking along -Z.
Placement placeFrames(const std::vector<PanoramaFrame>& frames, const PlacementSettings& settings);

// A light source the footage saturated: a direction in the environment (unit, world) and its
// angular radius, or, when `frame` >= 0, a pixel rectangle of that frame; and its radiance.
struct LightSource {
  std::optional<std::array<double, 3>> direction;
  double radiusDeg = 0.5;
  int frame = -1;
  cv::Rect region;
  std::array<float, 3> radiance{0, 0, 0};
};

// How the directions no frame saw are filled.
//  - Nearest: the colour of the nearest seen texel (Wang et al.).
//  - SkyModel: the sky above the horizon from a model fitted to the seen, unclipped sky: the
//    Preetham clear sky (turbidity and sun; the sun from a direction light above the horizon
//    when one is given, else fitted), the CIE overcast sky (Huang et al.) or a uniform sky,
//    whichever fits best (sky_model.h); the ground below it a Lambertian ground of the seen
//    ground's albedo lit by that sky (the seen ground's mean radiance; with no ground seen,
//    albedo 0.125). Near the coverage both fade into the nearest seen colour (no seam). With no sky
//    seen, the overcast sky that lights the seen ground; with nothing seen, Nearest. unseen_fill.h
//    has the details.
enum class UnseenFill { Nearest, SkyModel };

struct EquirectSettings {
  int width = 512;  // height = width / 2
  std::vector<LightSource> lights;
  // The model fill measured better on all six shared HDRs (pluvia report envmap: drop colour
  // error at 24 frames 24 -> 20 % on city, 8.4 -> 6.4 % on sunset, equal where it falls back).
  UnseenFill fill = UnseenFill::SkyModel;
};

struct PanoramaResult {
  EquirectMap radiance;   // filled everywhere
  std::string fillModel;  // what filled the unseen directions ("nearest", "preetham T 3.1, ...")
  cv::Mat coverage;       // CV_8UC1 width x height: nonzero where a frame saw the direction
  double coveredFraction = 0.0;  // of the sphere's solid angle
  std::vector<float> gains;      // per frame exposure gain applied (1 for frame 0)
};

// Renders the placed frames into an equirect map: per texel direction, a feather-weighted mean
// of the frames that see it (after per-frame exposure gains matched on the overlaps); unseen
// texels take the nearest seen colour (wrapping in longitude); saturated pixels take the
// radiance of the light covering them (lights), else keep their clipped value. The fill copies
// what the footage recorded (clipped values included), never a light's radiance: a lamp at the
// edge of the frames is not smeared over the unseen sky.
PanoramaResult renderEquirect(const std::vector<PanoramaFrame>& frames, const Placement& placement,
                              const EquirectSettings& settings);

}  // namespace pluvia::envmap
