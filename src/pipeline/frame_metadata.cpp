#include "pipeline/frame_metadata.h"

#include <fmt/format.h>

#include "pluvia/version.h"

namespace pluvia {

std::map<std::string, std::string> frameMetadata(const Preset& preset,
                                                 const std::vector<StageInfo>& stages) {
  std::string presetJson = preset.json().dump();
  if (presetJson.size() > kMaxPresetMetadataBytes) {
    presetJson = fmt::format(
        "(not copied: the resolved preset is {} bytes, over the {}-byte limit; "
        "pluvia:presetHash identifies it)",
        presetJson.size(), kMaxPresetMetadataBytes);
  }
  std::map<std::string, std::string> metadata{{"pluvia:version", kVersion},
                                              {"pluvia:presetHash", preset.hash()},
                                              {"pluvia:preset", presetJson}};
  for (const StageInfo& stage : stages)
    if (stage.frameMetadata) metadata.merge(stage.frameMetadata(preset));
  return metadata;
}

}  // namespace pluvia
