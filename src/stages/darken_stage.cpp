// Darken: Starik and Werman's rainy-day look (Wang et al. section 5, "Scene Color"), by depth
// (stages/depth_grading.h): the rain between the camera and the scene greys and darkens what is
// far more than what is near.
#include "image/ops.h"
#include "stages/clip_plate_rain.h"
#include "stages/darken_settings.h"
#include "stages/depth_grading.h"
#include "stages/registry.h"

namespace pluvia {

StageInfo darkenStageInfo() {
  return makeStageInfo(
      darkenTable().section(), darkenSettings,
      {.noOpReason = [](const DarkenSettings& darken, const Preset&) -> std::string {
         return darken.amount == 0.0 ? "amount is 0" : "";
       },
       .note = [](const DarkenSettings& darken,
                  const Preset&) { return rainedPlateNote("darken", darken.overRain); },
       .reads =
           [](const DarkenSettings& darken, const Preset&) {
             std::vector<std::string> reads{"image"};
             if (darken.distanceMeters > 0.0) reads.push_back("depth");
             if (!darken.overRain) reads.push_back("plate_rain");
             return reads;
           },
       .cachedWork =
           [](const DarkenSettings& darken, const Preset&, const ClipInfo& clip,
              const std::string& framesKey, const ArtifactCache& cache) {
             return cachedPlateRainNote(clip, framesKey, cache, darken.overRain);
           },
       .create =
           [](const DarkenSettings& darken, const Preset&) {
             return std::make_unique<DepthGradingStage>(
                 "darken", darken.distanceMeters, darken.overRain,
                 [darken](Image& image, const std::vector<float>& weight) {
                   ops::darken(image, float(darken.amount), float(darken.darkening), weight.data());
                 });
           }});
}

}  // namespace pluvia
