#include "common.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "io/frame_list.h"
#include "io/sequence_pattern.h"
#include "stages/blur_settings.h"
#include "stages/lighting_settings.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/executable.h"
#include "util/fs.h"
#include "util/input_guard.h"
#include "util/log.h"
#include "util/parse_number.h"

namespace pluvia::cli {

std::pair<int64_t, int64_t> parseFrameRange(const std::string& text) {
  auto parseNumber = [&](const std::string& s) {
    const std::optional<int64_t> value = parseWholeNumber<int64_t>(s);
    if (!value)
      throw UsageError(fmt::format("--frames '{}': expected FIRST-LAST, e.g. 1001-1048", text));
    return *value;
  };
  size_t dash = text.find('-', 1);
  int64_t first = parseNumber(text.substr(0, dash));
  int64_t last = dash == std::string::npos ? first : parseNumber(text.substr(dash + 1));
  if (last < first)
    throw UsageError(fmt::format("--frames '{}': the last frame comes before the first", text));
  return {first, last};
}

void setFrames(RenderRequest& request, const std::string& text) {
  std::vector<int64_t> frames = parseFrameList(text);
  if (isContiguous(frames)) {
    request.firstFrame = frames.front();
    request.lastFrame = frames.back();
  } else {
    request.frameList = std::move(frames);
  }
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

void addStartFrameOption(CLI::App* cmd, std::optional<int64_t>& movieFirstFrame) {
  // Frame numbers beyond a trillion are no clip's; within them frame arithmetic cannot overflow.
  cmd->add_option("--start-frame", movieFirstFrame,
                  "the number of a movie's first frame (movies count from 0 otherwise), such as "
                  "1001: --frames, the rain and the output's frame numbers and timecode follow it")
      ->check(CLI::Range(int64_t(-1'000'000'000'000), int64_t(1'000'000'000'000)));
}

void addRenderOutputOptions(CLI::App* cmd, RenderOutputOptions& options) {
  options.codecOption = cmd->add_option(
      "--codec", options.codec,
      "movie codec: h264 (default), prores_4444, prores_422hq, dnxhr_hq, dnxhr_hqx, "
      "dnxhr_444 (ProRes and DNxHR in .mov or .mkv, DNxHR also in .mxf)");
  options.exrTypeOption =
      cmd->add_option("--exr-type", options.exrType, "EXR samples: half (default) or float")
          ->check(CLI::IsMember({"half", "float"}));
  options.exrCompressionOption = cmd->add_option(
      "--exr-compression", options.exrCompression,
      "EXR compression: piz (default), zip, zips, dwaa, dwab, b44, b44a, pxr24, rle, none");
  options.tiffTypeOption =
      cmd->add_option("--tiff-type", options.tiffType,
                      "TIFF samples: uint16 (default) or float (keeps values beyond [0, 1])")
          ->check(CLI::IsMember({"uint16", "float"}));
  cmd->add_option(
      "--aov", options.aov,
      "extra outputs: rain,matte,depth,lights,wet_ground,splash,ripples,glare,darken,blur,fog");
  cmd->add_option("--proxy", options.proxy,
                  "render at this fraction of the plate's size, in (0, 1], for quick looks");
  cmd->add_flag("--mkdir", options.makeFolders,
                "make the output's folder and every missing folder above it (without it, only a "
                "missing last folder is made)");
}

std::vector<std::string> RenderOutputOptions::aovs() const {
  static const std::vector<std::string> kKnown = {"rain",       "matte",  "depth",   "lights",
                                                  "wet_ground", "splash", "ripples", "glare",
                                                  "darken",     "blur",   "fog"};
  std::vector<std::string> list;
  for (size_t start = 0; !aov.empty() && start <= aov.size();) {
    const size_t comma = aov.find(',', start);
    const std::string name = aov.substr(start, comma - start);
    if (std::find(kKnown.begin(), kKnown.end(), name) == kKnown.end())
      throw UsageError(
          fmt::format("--aov: unknown output '{}' (known: {})", name, fmt::join(kKnown, ", ")));
    // Named twice, written once (the second copy made unnamed channels).
    if (std::find(list.begin(), list.end(), name) == list.end()) list.push_back(name);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return list;
}

std::vector<std::string> RenderOutputOptions::renderArguments() const {
  const RenderOutputOptions defaults;
  std::vector<std::string> arguments;
  if (codec != defaults.codec) arguments.insert(arguments.end(), {"--codec", codec});
  if (exrType != defaults.exrType) arguments.insert(arguments.end(), {"--exr-type", exrType});
  if (exrCompression != defaults.exrCompression)
    arguments.insert(arguments.end(), {"--exr-compression", exrCompression});
  if (tiffType != defaults.tiffType) arguments.insert(arguments.end(), {"--tiff-type", tiffType});
  if (!aov.empty())
    arguments.insert(arguments.end(), {"--aov", fmt::format("{}", fmt::join(aovs(), ","))});
  if (proxy != defaults.proxy)
    arguments.insert(arguments.end(), {"--proxy", fmt::format("{}", proxy)});
  if (makeFolders) arguments.push_back("--mkdir");
  return arguments;
}

const CLI::Validator& nonEmptyText() {
  static const CLI::Validator check(
      [](std::string& value) {
        return value.empty() ? std::string(
                                   "is empty (an unset shell variable?): give a value "
                                   "or leave the option out")
                             : std::string();
      },
      "NOT EMPTY");
  return check;
}

const CLI::Validator& finiteNumber() {
  static const CLI::Validator check(
      [](std::string& value) {
        try {
          if (std::isfinite(std::stod(value))) return std::string();
        } catch (const std::exception&) {
        }
        return "'" + value + "' is not a finite number";
      },
      "FINITE");
  return check;
}

void RenderOutputOptions::refuseOptionsNotFor(const std::string& output) const {
  const std::string extension = lowerExtension(output);
  const bool movie = isMovieExtension(output), exr = extension == "exr",
             tiff = extension == "tif" || extension == "tiff";
  if (codecOption && codecOption->count() && !movie)
    throw UsageError(
        fmt::format("--codec applies to a movie; {} is not one (its format is its "
                    "extension's)",
                    output));
  for (const CLI::Option* given : {exrTypeOption, exrCompressionOption})
    if (given && given->count() && !exr)
      throw UsageError(
          fmt::format("{} applies to EXR output; {} is not EXR", given->get_name(), output));
  if (tiffTypeOption && tiffTypeOption->count() && !tiff)
    throw UsageError(fmt::format("--tiff-type applies to TIFF output; {} is not TIFF", output));
}

void protectNamedInputs(const CLI::App& app) {
  static const std::set<std::string> kInputOptions = {
      "INPUT", "CLIP", "clips", "REFERENCE", "PRESET", "--env", "--hdr", "--lights", "--preset"};
  for (const CLI::App* command : app.get_subcommands()) {
    for (const CLI::Option* option : command->get_options())
      if (kInputOptions.count(option->get_name()) != 0) fs::protectInputs(option->results());
    protectNamedInputs(*command);
  }
}

void refuseOverwritingInput(const std::vector<std::string>& inputFiles, const std::string& option,
                            const std::vector<std::string>& outputs) {
  fs::protectInputs(inputFiles);
  for (const std::string& out : outputs) {
    if (out.empty()) continue;  // an optional output not asked for
    fs::claimOutput(out, option);
    // `inputFiles` and every other input of the run (the preset, --lights, a file the preset
    // names), by device and inode: any spelling or link of one.
    if (const std::string in = fs::protectedInputAt(out); !in.empty())
      throw UsageError(
          fmt::format("{} {} is the input file {}: refusing to overwrite it", option, out, in),
          {"write", {}, in});
  }
}

std::string findBesideInstall(const std::filesystem::path& relative) {
  std::vector<std::filesystem::path> roots = {std::filesystem::current_path()};
  if (!executablePath().empty())
    roots.insert(roots.begin(), executablePath().parent_path().parent_path());
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
  // Every shipped preset (base is what they extend, not one to render with).
  std::vector<std::string> names = shippedPresetNames();
  names.erase(std::remove(names.begin(), names.end(), "base"), names.end());
  cmd->add_option("-p,--preset", preset,
                  fmt::format("preset name ({}) or path", fmt::join(names, ", ")))
      ->required();
  cmd->add_option("--set", sets, "override KEY=VALUE (dotted key path, e.g. rain.rate_mm_h=40)");
  // Shorthands for the colour keys: the same overrides, applied after any --set.
  cmd->add_option_function<std::string>(
      "--in-colorspace",
      [&sets](const std::string& space) { sets.push_back("color.input=" + space); },
      "input colour space (name, alias or role in the OCIO config): --set color.input=SPACE");
  cmd->add_option_function<std::string>(
      "--out-colorspace",
      [&sets](const std::string& space) { sets.push_back("color.output=" + space); },
      "output colour space: --set color.output=SPACE");
  cmd->add_option_function<std::string>(
      "--ocio", [&sets](const std::string& path) { sets.push_back("color.config=" + path); },
      "OpenColorIO config file (default: $OCIO, else pluvia's built-in config): "
      "--set color.config=FILE");
}

}  // namespace pluvia::cli
