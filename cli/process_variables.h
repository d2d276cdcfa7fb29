#pragma once
// The environment variables pluvia reads, all of them here, once, in each binary's main()
// before any work; the libraries take what they say through their setters and read no
// environment of their own:
//   PLUVIA_PRESET_DIR    a folder searched first for preset names (preset::setPresetFolder)
//   PLUVIA_ASSET_DIR     a folder searched first for the stroke library (rain::setAssetFolder)
//   PLUVIA_COLMAP        the COLMAP program (sfm::setColmapProgram)
//   PLUVIA_RAIN_BACKEND  auto, egl or cpu: who draws the streaks (gpu::setRainBackend)
// (OCIO, the colour configuration, is OpenColorIO's own and read where the config is loaded.)

#include <string>

namespace pluvia {

// The variable's value; "" when unset.
std::string processVariable(const char* name);

// PLUVIA_RAIN_BACKEND alone (pluvia-bench-strokes links no other library). Throws pluvia::Error
// naming the variable and its value when it is not auto, egl or cpu.
void applyRainBackendVariable();

// All of them (pluvia).
void applyProcessVariables();

}  // namespace pluvia
