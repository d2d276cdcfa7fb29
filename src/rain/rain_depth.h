#pragma once
// How deep a camera sees rain as streaks (rain.far_m 0). Garg and Nayar ("When does a camera see
// rain?", ICCV 2005): a drop of diameter D is one pixel wide at z_m = f D (f the focal length in
// pixels); farther, its streak is narrower than a pixel and its contrast falls as z_m / z until
// it sinks into the noise, and that rain is seen as fog, not streaks. The depth counts in pixels,
// not metres: a 4K plate resolves drops a 640 px one loses.
//
// pluvia draws drops out to kVisibleDepthOverOnePixel times z_m of the median-volume drop of the
// rain (Marshall-Palmer, D0 = 3.67 / Lambda: 1.4 mm at 8 mm/h). The factor is what `pluvia
// match` found on three real daytime clips at 640 px (NTURain ra1 1.7 z_m, NTURain rb2 3.0,
// Pexels' heavy rain 1.2 at the match's 1 m floor: geometric mean 1.8): real footage shows its
// near drops as streaks and none of the pepper of far specks that drops drawn to 8 m give.
namespace pluvia::rain {

inline constexpr double kVisibleDepthOverOnePixel = 2.0;

// Median-volume diameter of Marshall-Palmer rain, mm (0.9 mm at 1 mm/h, 1.9 mm at 40 mm/h); the
// rate must be > 0.
double medianVolumeDiameterMm(double rainRateMmPerHour);

// kVisibleDepthOverOnePixel * focalPx * D0 * sizeScale, in metres (1.9 m for 8 mm/h on a 640 px
// wide 50 degree view; 5.7 m at 1920 px). Rate and sizeScale must be > 0.
double streakDepthMeters(double focalPx, double rainRateMmPerHour, double sizeScale = 1.0);

}  // namespace pluvia::rain
