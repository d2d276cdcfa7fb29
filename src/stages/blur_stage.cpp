// Blur: the scene seen through rain is softened by the light the drops scatter on its way
// (Wang et al. section 5, "Scene Blur"): a Gaussian of sigma pixels, mixed in by depth
// (stages/depth_grading.h): the scattered share of a ray grows with its path through the rain,
// so the near field stays sharp and the far softens.
#include "image/ops.h"
#include "stages/blur_settings.h"
#include "stages/clip_plate_rain.h"
#include "stages/depth_grading.h"
#include "stages/registry.h"

namespace pluvia {

StageInfo blurStageInfo() {
  return makeStageInfo(
      blurTable().section(), blurSettings,
      {.noOpReason = [](const BlurSettings& blur, const Preset&) -> std::string {
         return blur.sigmaPx == 0.0 ? "sigma_px is 0" : "";
       },
       .note = [](const BlurSettings& blur,
                  const Preset&) { return rainedPlateNote("blur", blur.overRain); },
       .reads =
           [](const BlurSettings& blur, const Preset&) {
             std::vector<std::string> reads{"image"};
             if (blur.distanceMeters > 0.0) reads.push_back("depth");
             if (!blur.overRain) reads.push_back("plate_rain");
             return reads;
           },
       .cachedWork =
           [](const BlurSettings& blur, const Preset&, const ClipInfo& clip,
              const std::string& framesKey, const ArtifactCache& cache) {
             return cachedPlateRainNote(clip, framesKey, cache, blur.overRain);
           },
       .create =
           [](const BlurSettings& blur, const Preset&) {
             return std::make_unique<DepthGradingStage>(
                 "blur", blur.distanceMeters, blur.overRain,
                 [blur](Image& image, const std::vector<float>& weight) {
                   ops::gaussianBlurToward(image, float(blur.sigmaPx), weight.data());
                 });
           }});
}

}  // namespace pluvia
