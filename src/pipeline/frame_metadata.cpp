#include "pipeline/frame_metadata.h"

#include <fmt/format.h>

#include "pluvia/version.h"

namespace pluvia {

std::map<std::string, std::string> frameMetadata(const Preset& preset) {
  std::string presetJson = preset.json().dump();
  if (presetJson.size() > kMaxPresetMetadataBytes) {
    presetJson = fmt::format(
        "(not copied: the resolved preset is {} bytes, over the {}-byte limit; "
        "pluvia:presetHash identifies it)",
        presetJson.size(), kMaxPresetMetadataBytes);
  }
  return {{"pluvia:version", kVersion},
          {"pluvia:presetHash", preset.hash()},
          {"pluvia:seed", std::to_string(int64_t(preset.number("rain.seed")))},
          {"pluvia:preset", presetJson}};
}

}  // namespace pluvia
