#include "process_variables.h"

#include "preset/preset.h"
#include "rain/stroke_library.h"
#include "sfm/colmap_runner.h"

namespace pluvia {

void applyProcessVariables() {
  applyRainBackendVariable();
  setPresetFolder(processVariable("PLUVIA_PRESET_DIR"));
  rain::setAssetFolder(processVariable("PLUVIA_ASSET_DIR"));
  sfm::setColmapProgram(processVariable("PLUVIA_COLMAP"));
}

}  // namespace pluvia
