#include "realism_render.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "common.h"
#include "io/image_file_writer.h"
#include "pipeline/render_job.h"
#include "stages/registry.h"

namespace pluvia::cli {
namespace {

void writePlate(const std::string& path, const cv::Mat3f& codes) {
  const cv::Mat3f unit = codes / 255.0f;
  std::vector<OutputChannel> channels;
  for (int c = 0; c < 3; ++c)
    channels.push_back({std::string(1, "RGB"[c]), unit.ptr<float>() + c, 3});
  writeImageFile(path, unit.cols, unit.rows, channels, {}, std::nullopt);
}

cv::Mat3f codesOf(const Image& image) {
  cv::Mat3f codes(image.height, image.width);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = image.rgba[(size_t(y) * image.width + x) * 4 + c];
        codes(y, x)[c] = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f);
      }
  return codes;
}

}  // namespace

PlateRenderer::PlateRenderer(const std::vector<cv::Mat3f>& plates, double fps, int filmedWidthPx)
    : folder_("pluvia-realism"), fps_(fps), filmedWidthPx_(filmedWidthPx) {
  for (size_t i = 0; i < plates.size(); ++i)
    writePlate((folder_.path() / fmt::format("plate.{:04d}.png", i)).string(), plates[i]);
}

std::vector<cv::Mat3f> PlateRenderer::render(const std::string& preset,
                                             const std::vector<std::string>& sets) const {
  RenderRequest request;
  request.input = (folder_.path() / "plate.####.png").string();
  request.output = OutputTarget::classify((folder_.path() / "rained.####.png").string());
  request.cacheDir = (folder_.path() / "cache").string();
  request.progress = false;
  request.filmedWidthPx = filmedWidthPx_;
  std::vector<std::string> overrides = sets;
  for (const char* off : {"wet_ground.enabled=false", "darken.enabled=false", "blur.enabled=false",
                          "fog.enabled=false"})
    overrides.push_back(off);
  overrides.push_back(fmt::format("camera.fps={:g}", fps_));
  const Preset resolved = loadPreset(preset, overrides);
  StageTimes times;
  RenderSession session(request, resolved, allStages(), times);
  session.prepareStages();
  std::vector<cv::Mat3f> rendered;
  for (int64_t frame : session.frames()) {
    FrameContext context = session.readFrame(frame);
    session.processFrame(context);
    session.toOutput(context.image);
    rendered.push_back(codesOf(context.image));
  }
  return rendered;
}

std::vector<cv::Mat3f> renderOnPlates(const std::vector<cv::Mat3f>& plates, double fps,
                                      int filmedWidthPx, const std::string& preset,
                                      const std::vector<std::string>& sets) {
  return PlateRenderer(plates, fps, filmedWidthPx).render(preset, sets);
}

}  // namespace pluvia::cli
