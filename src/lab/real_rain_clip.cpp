#include "lab/real_rain_clip.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "io/clip_reader.h"
#include "util/error.h"

namespace pluvia::lab {

using namespace derain;

std::string defaultClip(const std::string& sharedData) {
  if (sharedData.empty()) return "";
  const std::string pattern = sharedData + "/rain_real/nturain_ra1_real_rain_panning/%05d.jpg";
  return std::filesystem::exists(sharedData + "/rain_real/nturain_ra1_real_rain_panning/00001.jpg")
             ? pattern
             : "";
}

RealClip readRealClip(const std::string& path, int count, int widthPx) {
  std::unique_ptr<ClipReader> reader = openClip(path);
  const ClipInfo& info = reader->info();
  RealClip clip;
  // A sequence is named by its folder when its file names are only the frame number.
  const std::filesystem::path file(path);
  const std::string stem = file.stem().string();
  const bool numbersOnly = stem.find_first_not_of("%0123456789d#@") == std::string::npos;
  clip.name = numbersOnly && file.has_parent_path() ? file.parent_path().filename().string()
                                                    : file.filename().string();
  if (info.isMovie) clip.fps = info.fps;
  clip.filmedWidthPx = info.width;
  const double scale = double(widthPx) / info.width;
  const size_t n = std::min(info.frames.size(), size_t(count));
  if (n < 3)
    throw Error(fmt::format("report realism: {} has {} frames; a clean plate needs 3 or more", path,
                            info.frames.size()),
                {"report", {}, path});
  for (size_t i = 0; i < n; ++i) {
    const Image image = reader->read(info.frames[i]);
    cv::Mat rgba(image.height, image.width, CV_32FC4, const_cast<float*>(image.rgba.data()));
    cv::Mat rgb, small;
    cv::cvtColor(rgba, rgb, cv::COLOR_RGBA2RGB);
    cv::resize(rgb, small, cv::Size(widthPx, int(std::lround(info.height * scale))), 0, 0,
               cv::INTER_AREA);
    clip.frames.push_back(cv::Mat3f(small * 255.0));
  }
  return clip;
}

StreakStats measureLayers(const std::vector<cv::Mat3f>& frames,
                          const std::vector<CleanPlate>& plates,
                          std::vector<cv::Mat1f>* layersOut) {
  StreakStatsAccumulator accumulator;
  RainLayerFrame previous;
  for (size_t i = 0; i < frames.size(); ++i) {
    RainLayerFrame layer;
    layer.plateLuma = lumaOf(plates[i].plate, ChannelOrder::rgb);
    layer.layer = lumaOf(frames[i], ChannelOrder::rgb) - layer.plateLuma;
    layer.valid = plates[i].valid;
    accumulator.add(layer, i > 0 ? &previous : nullptr);
    if (layersOut) layersOut->push_back(layer.layer);
    previous = layer;
  }
  return accumulator.result();
}

std::vector<CleanPlate> cleanPlatesRgb(const std::vector<cv::Mat3f>& rgbFrames,
                                       const std::vector<int>& at) {
  std::vector<cv::Mat3f> bgr(rgbFrames.size());
  for (size_t i = 0; i < rgbFrames.size(); ++i)
    cv::cvtColor(rgbFrames[i], bgr[i], cv::COLOR_RGB2BGR);
  std::vector<CleanPlate> plates = at.empty() ? cleanPlates(bgr) : cleanPlatesAt(bgr, at);
  for (CleanPlate& plate : plates) cv::cvtColor(plate.plate, plate.plate, cv::COLOR_BGR2RGB);
  return plates;
}

}  // namespace pluvia::lab
