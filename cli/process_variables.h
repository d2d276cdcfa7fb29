#pragma once
// The environment variables pluvia reads, all of them here, once, in each binary's main()
// before any work; the libraries take what they say through their setters and read no
// environment of their own (kProcessVariables lists them: PLUVIA_PRESET_DIR for
// preset::setPresetFolder, PLUVIA_ASSET_DIR for rain::setAssetFolder, PLUVIA_COLMAP for
// sfm::setColmapProgram, PLUVIA_RAIN_BACKEND for gpu::setRainBackend). OCIO, the colour
// configuration, is OpenColorIO's own and read where the config is loaded.

#include <string>

namespace pluvia {

// What each variable does, for --help and the man page.
inline constexpr const char* kProcessVariables =
    "PLUVIA_PRESET_DIR: a folder searched first for preset names. PLUVIA_ASSET_DIR: a folder "
    "searched first for the stroke library. PLUVIA_COLMAP: the COLMAP program (default: colmap "
    "on the PATH). PLUVIA_RAIN_BACKEND: auto, egl or cpu, who draws the streaks (auto: a GPU's "
    "EGL device where there is one, else the CPU rasteriser). OCIO: the OpenColorIO config "
    "when the preset and --ocio name none.";

// The variable's value; "" when unset.
std::string processVariable(const char* name);

// PLUVIA_RAIN_BACKEND alone (pluvia-bench-strokes links no other library). Throws pluvia::Error
// naming the variable and its value when it is not auto, egl or cpu.
void applyRainBackendVariable();

// All of them (pluvia).
void applyProcessVariables();

}  // namespace pluvia
