// Built only by the test layers_wrong_way_fails, which expects this to fail to compile: a target
// that links pluvia_rain (and not pluvia_gpu) cannot include a gpu/ header.
#include "gpu/rain_renderer.h"
