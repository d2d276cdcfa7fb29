#pragma once
// A synthetic street (a textured corridor with boxes in it, open sky above) rendered on the GPU
// through the headless EGL context, with the exact z-depth of every pixel: the ground truth
// against which `pluvia report depth` measures structure-from-motion (COLMAP) poses and depth.
//
// The projection is pluvia's pinhole Camera (geometry/camera.h) exactly: focalPx, principal
// point, pixel centres at +0.5, row 0 at the top. The scene is lit by a fixed sun (Lambertian)
// and textured from world position with non-periodic procedural noise and sharp-edged blotches,
// so that feature matchers find many distinct features from frame to frame.
//
// This header exposes no GL, EGL or Eigen type (it began in pluvia_gpu, which has no Eigen): the
// Camera-taking entry points are templates, instantiated in the caller's translation unit, which
// reads the Camera's members into a plain SyntheticView (defaultSyntheticCameraPath's CameraPath
// is only declared here). The GL work uses pluvia_gpu's context and object helpers
// (gpu/egl_context.h, gpu/gl_objects.h, gpu/shader_program.h).
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "image/image.h"

namespace pluvia {
class CameraPath;  // geometry/camera_path.h
}

namespace pluvia::lab {

// A box standing on the ground (y from 0 to heightMeters), axis-aligned.
struct SyntheticBox {
  double centerXMeters = 0.0;
  double centerZMeters = 0.0;
  double sizeXMeters = 1.0;
  double sizeZMeters = 1.0;
  double heightMeters = 1.0;
};

// The corridor: ground y = 0 for |x| <= halfWidth and backWallZ <= z <= openEndZ, side walls
// at x = -halfWidth and x = +halfWidth, a back wall at z = backWallZ, all wallHeight tall. The
// end at z = openEndZ (behind the default cameras) is open, and so is the sky.
struct SyntheticScene {
  double halfWidthMeters = 6.0;
  double backWallZMeters = -40.0;
  double openEndZMeters = 10.0;
  double wallHeightMeters = 8.0;
  std::vector<SyntheticBox> boxes;
};

// 12 m wide, 40 m deep (from z = 0 to the back wall), 8 m walls, four boxes at 8 to 32 m.
SyntheticScene defaultSyntheticScene();

// The sky's linear RGB for a view direction whose unit vector has world y component `unitUp`
// (the same formula as the fragment shader; below the horizon it is the horizon colour).
std::array<float, 3> syntheticSkyRgb(double unitUp);

// A pinhole view in plain numbers: the fields of pluvia::Camera.
struct SyntheticView {
  int width = 0;
  int height = 0;
  double focalPx = 1.0;
  double cx = 0.0;
  double cy = 0.0;
  std::array<double, 9> worldFromCamera = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
  std::array<double, 3> positionMeters = {0, 0, 0};

  // From a pluvia::Camera (or anything with its members and Eigen-like accessors).
  template <typename CameraT>
  static SyntheticView fromCamera(const CameraT& camera) {
    SyntheticView view;
    view.width = camera.width;
    view.height = camera.height;
    view.focalPx = camera.focalPx;
    view.cx = camera.cx;
    view.cy = camera.cy;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) view.worldFromCamera[r * 3 + c] = camera.worldFromCamera(r, c);
      view.positionMeters[r] = camera.positionMeters[r];
    }
    return view;
  }
  // Back to a pluvia::Camera (or anything with its members and Eigen-like accessors).
  template <typename CameraT>
  CameraT toCamera() const {
    CameraT camera;
    camera.width = width;
    camera.height = height;
    camera.focalPx = focalPx;
    camera.cx = cx;
    camera.cy = cy;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) camera.worldFromCamera(r, c) = worldFromCamera[r * 3 + c];
      camera.positionMeters[r] = positionMeters[r];
    }
    return camera;
  }
};

// One pose of the default path, in the convention of geometry/camera_path.h's CameraPose
// (yaw positive turns right, pitch positive looks up; worldFromCamera = Ry(-yaw) Rx(pitch)
// Rz(-roll)), ready for CameraPath::fromKeys.
struct SyntheticPathKey {
  double frame = 0.0;
  std::array<double, 3> positionMeters = {0, 0, 0};
  double yawDeg = 0.0;
  double pitchDeg = 0.0;
  double rollDeg = 0.0;
};

// Intrinsics of the default path's camera: horizontal field of view 60 degrees, principal point
// at the image centre.
inline constexpr double kSyntheticHfovDeg = 60.0;
inline constexpr double kSyntheticCameraHeightMeters = 1.6;
SyntheticView defaultSyntheticIntrinsics(int width, int height);

// The default path for the depth report: frameCount frames (0 .. frameCount-1) walking 0.05 m
// per frame down the corridor (-Z) at 1.6 m, drifting 0.01 m per frame to the right and
// yawing from -2 to +2 degrees, pitched 3 degrees down: enough translation for parallax.
std::vector<SyntheticPathKey> defaultSyntheticPath(int frameCount = 48);

// `intrinsics` placed at `key` (its pose replaced).
SyntheticView syntheticViewAt(const SyntheticView& intrinsics, const SyntheticPathKey& key);

// The default path as a CameraPath (the caller includes geometry/camera_path.h): the keys of
// defaultSyntheticPath(frameCount) on the camera of defaultSyntheticIntrinsics(width, height).
CameraPath defaultSyntheticCameraPath(int width, int height, int frameCount = 48);

class SyntheticSceneRenderer {
 public:
  // Creates its own headless GL context and the render targets of width x height. Throws
  // pluvia::Error when no context can be made or the size is out of range.
  SyntheticSceneRenderer(int width, int height, SyntheticScene scene = defaultSyntheticScene());
  ~SyntheticSceneRenderer();
  SyntheticSceneRenderer(const SyntheticSceneRenderer&) = delete;
  SyntheticSceneRenderer& operator=(const SyntheticSceneRenderer&) = delete;

  // RGB linear 0..1 (alpha 1) and plane "depth": z-depth in metres along the optical axis,
  // +infinity for sky. The view's size must equal the renderer's.
  Image render(const SyntheticView& view);
  // The same from a pluvia::Camera.
  template <typename CameraT>
  Image render(const CameraT& camera) {
    return render(SyntheticView::fromCamera(camera));
  }

  const SyntheticScene& scene() const;
  // "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 ..."
  std::string deviceDescription() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pluvia::lab
