#pragma once
// What every `pluvia bench` mode times with: the median of a run of measurements
// (util/median.h), and the process's CPU time.
#include "util/median.h"

namespace pluvia {

// CPU time of the whole process (every thread, llvmpipe's rasteriser threads included), in ms:
// on a machine shared with other jobs it varies less than the wall time.
double processCpuMs();

}  // namespace pluvia
