// Perspective frames cut from an equirect environment, recorded as an 8-bit sRGB camera would.
#include "envmap/perspective_view.h"

#include <algorithm>
#include <cmath>

#include "image/srgb.h"
#include "util/parallel.h"

namespace pluvia::envmap {

RecordedFrame recordView(const EquirectMap& environment, const CameraPose& pose, int width,
                         int height, double exposure) {
  RecordedFrame out;
  out.frame.linearRgb = cv::Mat(height, width, CV_32FC3, cv::Scalar::all(0));
  out.frame.saturated = cv::Mat(height, width, CV_8UC1, cv::Scalar::all(0));
  out.displayRgb8 = cv::Mat(height, width, CV_8UC3, cv::Scalar::all(0));
  if (width <= 0 || height <= 0 || environment.empty()) return out;

  // 8-bit code -> linear, once.
  std::array<float, 256> decode{};
  for (int i = 0; i < 256; ++i) decode[i] = float(srgbDecode(i / 255.0));

  const double f = pose.focalPx > 0 ? pose.focalPx : double(width);
  const cv::Matx33d& r = pose.cameraToWorld;
  forEachRow(height, [&](int y) {
    auto* lin = out.frame.linearRgb.ptr<cv::Vec3f>(y);
    auto* sat = out.frame.saturated.ptr<uchar>(y);
    auto* disp = out.displayRgb8.ptr<cv::Vec3b>(y);
    for (int x = 0; x < width; ++x) {
      // Camera looks along -Z, +X right, +Y up; row 0 at the top.
      const cv::Vec3d cam((x + 0.5 - 0.5 * width) / f, -(y + 0.5 - 0.5 * height) / f, -1.0);
      cv::Vec3d world = r * cam;
      world /= cv::norm(world);
      const auto rad =
          sampleEquirect(environment, float(world[0]), float(world[1]), float(world[2]));
      bool clipped = false;
      for (int c = 0; c < 3; ++c) {
        const double v = std::max(0.0, double(rad[c]) * exposure);
        const double code = std::round(std::min(1.0, srgbEncode(std::min(v, 1.0))) * 255.0);
        const int q = std::clamp(int(code), 0, 255);
        if (q >= 255) clipped = true;
        disp[x][c] = uchar(q);
        lin[x][c] = decode[q];
      }
      sat[x] = clipped ? 255 : 0;
    }
  });
  return out;
}

CameraPose panPose(double yawDeg, double pitchDeg, double horizontalFovDeg, int width) {
  const double yaw = yawDeg * CV_PI / 180.0;
  const double pitch = pitchDeg * CV_PI / 180.0;
  // Positive yaw turns the forward direction (-Z) toward +X: a rotation about +Y by -yaw.
  const double cy = std::cos(-yaw), sy = std::sin(-yaw);
  const cv::Matx33d ry(cy, 0, sy, 0, 1, 0, -sy, 0, cy);
  // Positive pitch tilts -Z toward +Y: a rotation about +X by +pitch.
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const cv::Matx33d rx(1, 0, 0, 0, cp, -sp, 0, sp, cp);
  CameraPose pose;
  pose.cameraToWorld = ry * rx;
  const double halfFov = std::clamp(horizontalFovDeg, 1.0, 179.0) * CV_PI / 360.0;
  pose.focalPx = 0.5 * width / std::tan(halfFov);
  return pose;
}

}  // namespace pluvia::envmap
