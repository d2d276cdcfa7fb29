#pragma once
// The thin lens that defocuses the drops (Garg and Nayar: defocus blur by depth). Focal length
// from the camera's pixel focal length and the sensor width; the circle of confusion of a point
// at distance d with the lens focused at s and aperture A = f / N:
//   c = A |d - s| / d * f / (s - f)   (on the sensor, mm)
namespace pluvia::rain {

struct ThinLens {
  double focalMm = 0.0;
  double fNumber = 0.0;  // 0: a pinhole, nothing is defocused
  double focusMeters = 0.0;
  double pxPerMm = 1.0;  // image width over sensor width

  // The lens of a camera `widthPx` wide with focal length `focalPx`; a pinhole when the focus or
  // the aperture is 0 or the focus is nearer than the focal length.
  static ThinLens of(double focalPx, int widthPx, double sensorWidthMm, double focusMeters,
                     double fNumber);
  bool defocuses() const { return fNumber > 0.0; }
  // Diameter of the circle of confusion in pixels at z-depth `depthMeters` (> 0).
  double blurPx(double depthMeters) const;
  // The nearest distance at which the blur is at most `blurPx`, between the camera and the focus
  // (the focus itself for a pinhole).
  double nearestWithBlurMeters(double blurPx) const;
};

}  // namespace pluvia::rain
