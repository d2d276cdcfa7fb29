#pragma once
// A built-in environment for the optics report and tests when no HDR is at hand: a sky graded
// from horizon to zenith, darker ground, a warm sun 30 degrees up (a disc of 1.5 degrees radius,
// 2000 times brighter than the sky: a hard case for SH ringing and for the reference's noise),
// and two coloured walls so the channels differ. Procedural, so it ships with the code.
#include "image/equirect.h"

namespace pluvia::lab {

EquirectMap builtinTestEnvironment(int width = 512);

}  // namespace pluvia::lab
