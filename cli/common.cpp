#include "common.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "stages/blur_settings.h"
#include "stages/lighting_settings.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/log.h"

namespace pluvia::cli {

std::pair<int64_t, int64_t> parseFrameRange(const std::string& text) {
  auto parseNumber = [&](const std::string& s) {
    size_t used = 0;
    int64_t value = 0;
    try {
      value = std::stoll(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != s.size())
      throw UsageError(fmt::format("--frames '{}': expected FIRST-LAST, e.g. 1001-1048", text));
    return value;
  };
  size_t dash = text.find('-', 1);
  int64_t first = parseNumber(text.substr(0, dash));
  int64_t last = dash == std::string::npos ? first : parseNumber(text.substr(dash + 1));
  if (last < first)
    throw UsageError(fmt::format("--frames '{}': the last frame comes before the first", text));
  return {first, last};
}

void checkProxyScale(double scale) {
  if (!(scale > 0.0 && scale <= 1.0))
    throw UsageError(fmt::format(
        "--proxy {:g}: the scale must be in (0, 1] (0.5 renders at half size, 1 at full size)",
        scale));
}

Preset loadPreset(const std::string& nameOrPath, const std::vector<std::string>& overrides) {
  return Preset::resolve(nameOrPath, overrides, presetSchema());
}

Preset loadPresetForProxy(const std::string& nameOrPath, const std::vector<std::string>& overrides,
                          double scale) {
  Preset fullSize = loadPreset(nameOrPath, overrides);
  if (scale == 1.0) return fullSize;
  std::vector<std::string> scaled = overrides;
  auto setScaled = [&](const std::string& key, double fullSizeValue, double proxyValue) {
    if (proxyValue == fullSizeValue) return;  // 0 stays 0
    scaled.push_back(fmt::format("{}={:g}", key, proxyValue));
    log::info(fmt::format("proxy: {} {:g} -> {:g}", key, fullSizeValue, proxyValue));
  };
  const double sigmaPx = blurSettings(fullSize).sigmaPx;
  setScaled("blur.sigma_px", sigmaPx, sigmaPx * scale);
  const nlohmann::json lights = lightingSettings(fullSize).lights;
  for (size_t i = 0; i < lights.size(); ++i) {
    if (lights[i].value("type", "") != "region") continue;
    auto setRegionField = [&](const char* field, double proxyMinimum) {
      const double px = lights[i].at(field).get<double>();
      setScaled(fmt::format("lighting.lights.{}.{}", i, field), px,
                std::max(proxyMinimum, std::round(px * scale)));
    };
    setRegionField("x", -INFINITY);
    setRegionField("y", -INFINITY);
    setRegionField("width", 1.0);  // a region keeps at least one pixel
    setRegionField("height", 1.0);
  }
  return loadPreset(nameOrPath, scaled);
}

std::string joinCommandLine(int argc, char** argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    std::string arg = argv[i];
    bool plain = !arg.empty() && arg.find_first_of(" \t'\"$\\;&|<>*?()") == std::string::npos;
    if (!plain) {
      std::string quoted = "'";
      for (char c : arg) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      arg = quoted + "'";
    }
    line += (i ? " " : "") + arg;
  }
  return line;
}

void refuseOverwritingInput(const std::vector<std::string>& inputFiles, const std::string& option,
                            const std::vector<std::string>& outputs) {
  for (const std::string& out : outputs)
    for (const std::string& in : inputFiles)
      if (fs::samePath(out, in))
        throw UsageError(
            fmt::format("{} {} is the input file {}: refusing to overwrite it", option, out, in),
            {"write", {}, in});
}

std::string findBesideInstall(const std::filesystem::path& relative) {
  std::error_code ec;
  const std::filesystem::path binary = std::filesystem::read_symlink("/proc/self/exe", ec);
  std::vector<std::filesystem::path> roots = {std::filesystem::current_path()};
  if (!ec) roots.insert(roots.begin(), binary.parent_path().parent_path());
  for (const auto& root : roots) {
    if (std::filesystem::exists(root / relative))
      return (root / relative).lexically_normal().string();
  }
  return "";
}

void addClipPresetOptions(CLI::App* cmd, std::string& input, std::string& preset,
                          std::vector<std::string>& sets) {
  cmd->add_option("INPUT", input,
                  "movie (mp4/mov/avi), image sequence (plate.####.exr, plate.%04d.png) or image")
      ->required();
  cmd->add_option("-p,--preset", preset, "preset name (drizzle, moderate, heavy, storm) or path")
      ->required();
  cmd->add_option("--set", sets, "override KEY=VALUE (dotted key path, e.g. rain.rate_mm_h=40)");
}

}  // namespace pluvia::cli
