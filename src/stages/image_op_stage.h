#pragma once
// A stage that applies one operation to every frame's image and needs nothing else: the blur and
// darken stages, whose StageInfo::create gives the operation with its settings bound.
#include <functional>
#include <utility>

#include "image/image.h"
#include "pipeline/stage.h"

namespace pluvia {

class ImageOpStage : public Stage {
 public:
  explicit ImageOpStage(std::function<void(Image&)> op) : op_(std::move(op)) {}
  void process(ClipContext&, FrameContext& frame) override { op_(frame.image); }

 private:
  std::function<void(Image&)> op_;
};

}  // namespace pluvia
