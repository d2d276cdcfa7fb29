#pragma once
// The rain filmed through the plate camera's own blur. Every element of a plate is seen through
// one lens, sensor, demosaicing and codec: a still edge there is a step blurred by a Gaussian of
// the plate's sigma (derain/motion_blur.h measures it), and real rain streaks are as soft. Across
// the streaks of real heavy daytime rain (the Pexels clip at 640 px, the layer against a temporal
// median) the layer falls to 0.72 of its peak 1 px to the side and 0.36 at 2 px; across pluvia's
// drawn streaks, to 0.41 and 0.05. The renderer draws its thinnest streaks minWidthPx wide (an
// equivalent width: a Gaussian of minWidthPx / sqrt(2 pi)), a blur already; the plate's blur
// adds the rest, in quadrature, to the premultiplied rain layer, which is then composited over
// the plate again. This is the compositor's match of a CG element's softness to its plate.
#include <vector>

#include "image/image.h"
#include "pipeline/stage.h"

namespace pluvia {

// The sigma, px, to blur a rain layer by so that its thinnest streaks are as soft as the plate's
// still edges (`plateStillBlurPx`, the sigma of their Gaussian): sqrt(plate^2 - drawn^2) with
// drawn = minDrawnWidthPx / sqrt(2 pi); 0 where the plate is as sharp or its blur unknown (0).
double rainBlurBeyondDrawnPx(double plateStillBlurPx, double minDrawnWidthPx);

// The sigma, px, the rain stage blurs its layer by on `clip`: rainBlurBeyondDrawnPx of the
// plate's still-edge blur (stages/plate_shutter.h's clipPlateStillBlurPx), or 0 on a night plate
// (`nightPlate`), whose strongest edges are lamps' glows and soft shadows: their widths measure
// the glow, not the lens (a real street-lamp clip reads sigma 2.15 px at 640 px), and softened
// by that its rain vanished (coverage x0.01 of real). Logs which and why.
double rainSofteningPx(ClipContext& clip, double minDrawnWidthPx, bool nightPlate);

// Blurs the rain planes ("rain.R", "rain.G", "rain.B", "rain.A") of `frame` by `sigmaPx` and
// composites them over `plateRgba` (the frame before the rain: interleaved RGBA, one value per
// frame.rgba value) into frame.rgba's RGB: rain + (1 - A) B, "matte" = A; a pixel with no rain
// keeps the plate exactly. sigmaPx 0 leaves the frame as it is.
void blurRainOverPlate(Image& frame, const std::vector<float>& plateRgba, double sigmaPx);

}  // namespace pluvia
