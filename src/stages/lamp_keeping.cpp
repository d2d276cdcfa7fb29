#include "stages/lamp_keeping.h"

#include "stages/clip_still.h"
#include "stages/plate_lights.h"
#include "util/log.h"

namespace pluvia {

void findNightPlate(ClipContext& clip) {
  if (clip.nightPlate) return;
  // A stage run alone over one image (no clip to make a still of) keeps nothing.
  clip.nightPlate = clip.clip && clip.readWorking && isNightPlate(plateLuminance(clipStill(clip)));
  if (*clip.nightPlate)
    log::info(
        "grading: a night plate: the lamps in their own glows are kept as the plate holds "
        "them (wet ground, darken, blur and fog leave them)");
}

const std::vector<float>& frameLampShare(const ClipContext& clip, FrameContext& frame) {
  if (!frame.lampShare)
    frame.lampShare =
        clip.nightPlate.value_or(false) ? lampShare(frame.image) : std::vector<float>();
  return *frame.lampShare;
}

KeptLamps::KeptLamps(const Image& before, const std::vector<float>& share) {
  if (share.size() != before.pixelCount()) return;
  for (size_t i = 0; i < share.size(); ++i) {
    if (share[i] <= 0.0f) continue;
    const float* p = &before.rgba[i * 4];
    kept_.push_back({i, share[i], {p[0], p[1], p[2]}});
  }
}

void KeptLamps::restore(Image& after) const {
  for (const Kept& k : kept_) {
    float* p = &after.rgba[k.pixel * 4];
    for (int c = 0; c < 3; ++c) p[c] += k.share * (k.rgb[c] - p[c]);
  }
}

}  // namespace pluvia
