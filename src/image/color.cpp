#include "image/color.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <tuple>

#include <OpenColorIO/OpenColorIO.h>
#include <fmt/format.h>

#include "image/transfer_lut.h"

#include "util/error.h"
#include "util/fs.h"
#include "util/input_guard.h"
#include "util/parallel.h"

namespace OCIO = OCIO_NAMESPACE;

namespace pluvia {
namespace {

// Exact simplifications only (folding matrices and gammas). The default level's approximations
// (fast pow, curves baked into LUTs) measured no faster on these transforms, and its LUTs could
// break the 1e-6 accuracy of the transfer curves. A conversion without channel crosstalk (the
// curves) runs through pluvia's own table instead (transfer_lut.h: within 1e-6, several times
// faster); one with crosstalk (ACEScg's matrix) through this processor.
constexpr OCIO::OptimizationFlags kOptimization = OCIO::OPTIMIZATION_LOSSLESS;
// Rows below which a band is not worth a task of its own.
constexpr int kMinRowsPerBand = 16;

OCIO::ColorSpaceRcPtr makeColorSpace(const std::string& name, const std::string& family,
                                     const std::string& description) {
  OCIO::ColorSpaceRcPtr space = OCIO::ColorSpace::Create();
  space->setName(name.c_str());
  space->setFamily(family.c_str());
  space->setDescription(description.c_str());
  return space;
}

// A piecewise power curve (linear toe) decoding to linear when applied forward.
OCIO::TransformRcPtr transferCurve(double gamma, double offset) {
  OCIO::ExponentWithLinearTransformRcPtr curve = OCIO::ExponentWithLinearTransform::Create();
  const double gammas[4] = {gamma, gamma, gamma, 1.0};
  const double offsets[4] = {offset, offset, offset, 0.0};
  curve->setGamma(gammas);
  curve->setOffset(offsets);
  return curve;
}

OCIO::ConstConfigRcPtr buildBuiltinConfig() {
  OCIO::ConfigRcPtr config = OCIO::Config::Create();
  config->setDescription(
      "pluvia built-in colour config (OCIO built-in transforms; reference: linear Rec.709)");

  OCIO::ColorSpaceRcPtr linear =
      makeColorSpace("linear-rec709", "scene-linear", "Scene-linear, Rec.709 primaries, D65");
  linear->setEncoding("scene-linear");
  config->addColorSpace(linear);

  OCIO::ColorSpaceRcPtr acescg =
      makeColorSpace("ACEScg", "scene-linear", "Scene-linear, ACES AP1 primaries");
  acescg->setEncoding("scene-linear");
  OCIO::BuiltinTransformRcPtr ap1ToRec709 = OCIO::BuiltinTransform::Create();
  ap1ToRec709->setStyle("UTILITY - ACES-AP1_to_LINEAR-REC709_BFD");
  acescg->setTransform(ap1ToRec709, OCIO::COLORSPACE_DIR_TO_REFERENCE);
  config->addColorSpace(acescg);

  OCIO::ColorSpaceRcPtr srgb =
      makeColorSpace("sRGB", "display", "sRGB piecewise transfer curve, Rec.709 primaries");
  srgb->setEncoding("sdr-video");
  srgb->setTransform(transferCurve(2.4, 0.055), OCIO::COLORSPACE_DIR_TO_REFERENCE);
  config->addColorSpace(srgb);

  OCIO::ColorSpaceRcPtr rec709 =
      makeColorSpace("rec709", "display", "Rec.709 camera OETF, Rec.709 primaries");
  rec709->setEncoding("sdr-video");
  rec709->setTransform(transferCurve(1.0 / 0.45, 0.099), OCIO::COLORSPACE_DIR_TO_REFERENCE);
  config->addColorSpace(rec709);

  // Video with BT.2020 primaries (the Rec.709 OETF, which BT.2020 keeps for SDR), to linear
  // Rec.709 by ITU-R BT.2087's matrix.
  OCIO::ColorSpaceRcPtr rec2020 =
      makeColorSpace("rec2020", "display", "Rec.709/2020 camera OETF, BT.2020 primaries");
  rec2020->setEncoding("sdr-video");
  OCIO::GroupTransformRcPtr rec2020ToReference = OCIO::GroupTransform::Create();
  rec2020ToReference->appendTransform(transferCurve(1.0 / 0.45, 0.099));
  OCIO::MatrixTransformRcPtr bt2020ToBt709 = OCIO::MatrixTransform::Create();
  const double bt2087[16] = {1.660491,  -0.587641, -0.072850, 0.0,       -0.124550, 1.132900,
                             -0.008349, 0.0,       -0.018151, -0.100579, 1.118730,  0.0,
                             0.0,       0.0,       0.0,       1.0};
  bt2020ToBt709->setMatrix(bt2087);
  rec2020ToReference->appendTransform(bt2020ToBt709);
  rec2020->setTransform(rec2020ToReference, OCIO::COLORSPACE_DIR_TO_REFERENCE);
  config->addColorSpace(rec2020);

  OCIO::ColorSpaceRcPtr raw = makeColorSpace("raw", "utility", "Data: never converted");
  raw->setIsData(true);
  config->addColorSpace(raw);

  config->setRole(OCIO::ROLE_SCENE_LINEAR, "linear-rec709");
  config->setRole(OCIO::ROLE_DEFAULT, "linear-rec709");
  config->setRole(OCIO::ROLE_DATA, "raw");
  // OCIO requires a display; it lets viewers that load the saved config show our frames.
  config->addDisplayView("sRGB", "Standard", "sRGB", "");
  config->addDisplayView("sRGB", "Raw", "raw", "");
  config->validate();
  return config;
}

// Loading configs and building processors is slow (milliseconds): both are cached for the
// process, keyed by config path ("" for the built-in one).
std::mutex cacheMutex;

OCIO::ConstConfigRcPtr configFor(const std::string& given) {
  static std::map<std::string, OCIO::ConstConfigRcPtr> configs;
  const std::string configPath = chosenConfigPath(given);
  std::lock_guard lock(cacheMutex);
  auto found = configs.find(configPath);
  if (found != configs.end()) return found->second;
  OCIO::ConstConfigRcPtr config;
  const bool builtinUri = configPath.rfind("ocio://", 0) == 0;
  // Configs built into the library (ocio://default, ocio://cg-config-...) came with
  // OpenColorIO 2.2; an older library reads the URI as a file name that does not exist.
  if (builtinUri && OCIO::GetVersionHex() < 0x02020000)
    throw Error(fmt::format("the OpenColorIO config {}: configs built into OpenColorIO "
                            "(ocio:// URIs) need OpenColorIO 2.2 or later, and pluvia runs "
                            "with OpenColorIO {}; give the config's .ocio file instead",
                            configPath, OCIO::GetVersion()),
                {"color", {}, configPath});
  if (!configPath.empty() && !builtinUri) {
    fs::requireRegularFile(configPath, "the OpenColorIO config");
    fs::protectInputs({configPath});
  }
  try {
    config = configPath.empty() ? buildBuiltinConfig()
                                : OCIO::Config::CreateFromFile(configPath.c_str());
  } catch (const OCIO::Exception& e) {
    const bool fromEnvironment = given.empty() && !configPath.empty();
    throw Error(std::string("cannot load the OpenColorIO config ") +
                    (configPath.empty() ? "(built-in)" : configPath) +
                    (fromEnvironment ? " (from $OCIO)" : "") + ": " + e.what(),
                {"color", {}, configPath});
  }
  return configs.emplace(configPath, config).first->second;
}

// Spaces that hold display-encoded sRGB (8-bit files) in the usual configs, best first: the
// built-in one, the ACES CG and studio configs (OCIO 2), the ACES 1.x config, and plain names.
constexpr const char* kSrgbEncodedNames[] = {"sRGB",
                                             "sRGB - Texture",
                                             "srgb_tx",
                                             "Utility - sRGB - Texture",
                                             "sRGB Encoded Rec.709 (sRGB)",
                                             "srgb_texture",
                                             "sRGB - Display",
                                             "srgb_display"};
// Roles that name such a space when none of the names above exists.
constexpr const char* kSrgbEncodedRoles[] = {"texture_paint", "matte_paint"};

std::vector<std::string> namesIn(const OCIO::ConstConfigRcPtr& config) {
  std::vector<std::string> names;
  for (int i = 0; i < config->getNumColorSpaces(); ++i)
    names.emplace_back(config->getColorSpaceNameByIndex(i));
  return names;
}

// The colour space's own name (OCIO also resolves roles and aliases); throws when unknown.
std::string resolveName(const OCIO::ConstConfigRcPtr& config, const std::string& name,
                        const std::string& configPath) {
  if (OCIO::ConstColorSpaceRcPtr space = config->getColorSpace(name.c_str()))
    return space->getName();
  std::string available;
  for (const std::string& known : namesIn(config))
    available += (available.empty() ? "" : ", ") + known;
  const std::string used = chosenConfigPath(configPath);
  throw Error("unknown colour space '" + name + "' in the config " +
                  (used.empty() ? std::string("(built-in)") : used) + " (available: " + available +
                  "; roles such as scene_linear name spaces too)",
              {"color", {}, used});
}

// A processor and, when it has no channel crosstalk, its lookup table (transfer_lut.h).
struct Conversion {
  OCIO::ConstCPUProcessorRcPtr processor;
  std::shared_ptr<const TransferLut> lut;
};

// RGB triples through the processor itself.
void applyExactly(const OCIO::ConstCPUProcessorRcPtr& processor, float* rgb, size_t count) {
  OCIO::PackedImageDesc packed(rgb, static_cast<long>(count), 1, OCIO::CHANNEL_ORDERING_RGB,
                               OCIO::BIT_DEPTH_F32, sizeof(float), 3 * sizeof(float),
                               static_cast<ptrdiff_t>(count * 3 * sizeof(float)));
  processor->apply(packed);
}

// A LUT file bigger than this is not a LUT (a 129^3 cube as text is about 60 MB).
constexpr uintmax_t kMaxLutFileBytes = uintmax_t(1) << 30;

// Throws pluvia::Error when a FileTransform in `transform` (or in the spaces it names, `seen`
// guarding against cycles) reads something that is not a LUT file: a device (/dev/zero), a FIFO
// or a folder, or a file over kMaxLutFileBytes. OpenColorIO would read such a source until
// memory runs out. A source it cannot find is left to OpenColorIO's own message.
void refuseHostileLuts(const OCIO::ConstConfigRcPtr& config,
                       const OCIO::ConstTransformRcPtr& transform, const std::string& configPath,
                       std::set<std::string>& seen);

void refuseHostileLutsOfSpace(const OCIO::ConstConfigRcPtr& config, const std::string& name,
                              const std::string& configPath, std::set<std::string>& seen) {
  OCIO::ConstColorSpaceRcPtr space = config->getColorSpace(name.c_str());
  if (!space || !seen.insert(space->getName()).second) return;
  for (auto direction : {OCIO::COLORSPACE_DIR_TO_REFERENCE, OCIO::COLORSPACE_DIR_FROM_REFERENCE})
    refuseHostileLuts(config, space->getTransform(direction), configPath, seen);
}

void refuseHostileLuts(const OCIO::ConstConfigRcPtr& config,
                       const OCIO::ConstTransformRcPtr& transform, const std::string& configPath,
                       std::set<std::string>& seen) {
  if (!transform) return;
  if (auto group = OCIO::DynamicPtrCast<const OCIO::GroupTransform>(transform)) {
    for (int i = 0; i < group->getNumTransforms(); ++i)
      refuseHostileLuts(config, group->getTransform(i), configPath, seen);
  } else if (auto space = OCIO::DynamicPtrCast<const OCIO::ColorSpaceTransform>(transform)) {
    refuseHostileLutsOfSpace(config, space->getSrc(), configPath, seen);
    refuseHostileLutsOfSpace(config, space->getDst(), configPath, seen);
  } else if (auto file = OCIO::DynamicPtrCast<const OCIO::FileTransform>(transform)) {
    std::string path;
    try {
      path = config->getCurrentContext()->resolveFileLocation(file->getSrc());
    } catch (const OCIO::Exception&) {
      return;
    }
    std::error_code error;
    const auto status = std::filesystem::status(path, error);
    if (error) return;
    if (!std::filesystem::is_regular_file(status))
      throw Error("the LUT '" + std::string(file->getSrc()) + "' (" + path +
                      ") is not a regular file (a device, FIFO or folder)",
                  {"color", {}, configPath});
    fs::protectInputs({path});
    const uintmax_t bytes = std::filesystem::file_size(path, error);
    if (!error && bytes > kMaxLutFileBytes)
      throw Error("the LUT '" + std::string(file->getSrc()) + "' (" + path + ") holds " +
                      std::to_string(bytes) + " bytes: more than any LUT (1 GiB)",
                  {"color", {}, configPath});
  }
}

Conversion conversionFor(const OCIO::ConstConfigRcPtr& config, const std::string& configPath,
                         const std::string& from, const std::string& to) {
  static std::map<std::tuple<std::string, std::string, std::string>, Conversion> conversions;
  const auto key = std::make_tuple(configPath, from, to);
  {
    std::lock_guard lock(cacheMutex);
    auto found = conversions.find(key);
    if (found != conversions.end()) return found->second;
  }
  std::set<std::string> seen;
  refuseHostileLutsOfSpace(config, from, configPath, seen);
  refuseHostileLutsOfSpace(config, to, configPath, seen);
  Conversion conversion;
  try {
    conversion.processor =
        config->getProcessor(from.c_str(), to.c_str())
            ->getOptimizedCPUProcessor(OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32, kOptimization);
    if (!conversion.processor->isNoOp() && !conversion.processor->hasChannelCrosstalk()) {
      OCIO::ConstCPUProcessorRcPtr processor = conversion.processor;
      conversion.lut = std::make_shared<const TransferLut>(
          [processor](float* rgb, size_t count) { applyExactly(processor, rgb, count); });
    }
  } catch (const OCIO::Exception& e) {
    throw Error("cannot convert colour from '" + from + "' to '" + to + "': " + e.what(),
                {"color", {}, configPath});
  }
  std::lock_guard lock(cacheMutex);
  return conversions.emplace(key, conversion).first->second;
}

}  // namespace

std::string chosenConfigPath(const std::string& configPath) {
  if (!configPath.empty()) return configPath;
  const char* environment = std::getenv("OCIO");
  return environment ? environment : "";
}

std::string describeConfig(const std::string& configPath) {
  const std::string used = chosenConfigPath(configPath);
  if (used.empty()) return "pluvia's built-in config";
  return used + (configPath.empty() ? " (from $OCIO)" : "");
}

std::vector<std::string> colorSpaceNamesOf(const std::string& name, const std::string& configPath) {
  OCIO::ConstConfigRcPtr config = configFor(configPath);
  OCIO::ConstColorSpaceRcPtr space =
      config->getColorSpace(resolveName(config, name, configPath).c_str());
  std::vector<std::string> names{space->getName()};
  for (size_t i = 0; i < space->getNumAliases(); ++i) names.emplace_back(space->getAlias(i));
  return names;
}

std::string srgbEncodedSpace(const std::string& configPath) {
  OCIO::ConstConfigRcPtr config = configFor(configPath);
  for (const char* name : kSrgbEncodedNames)
    if (OCIO::ConstColorSpaceRcPtr space = config->getColorSpace(name)) return space->getName();
  for (const char* role : kSrgbEncodedRoles)
    if (config->hasRole(role)) return config->getColorSpace(role)->getName();
  std::string names;
  for (const char* name : kSrgbEncodedNames)
    names += (names.empty() ? "" : ", ") + std::string(name);
  throw Error("the config " + describeConfig(configPath) +
                  " has no sRGB-encoded colour space for 8/16-bit files (looked for " + names +
                  " and the roles texture_paint, matte_paint): set color.input / color.output "
                  "(or --in-colorspace / --out-colorspace)",
              {"color", {}, chosenConfigPath(configPath)});
}

std::optional<std::string> videoEncodedSpace(const std::string& primaries,
                                             const std::string& configPath) {
  // The built-in config's names first, then those of the ACES and studio configs.
  static const std::vector<const char*> kRec709{"rec709", "Utility - Rec.709 - Camera",
                                                "Rec.709 - Camera", "rec709_camera"};
  static const std::vector<const char*> kRec2020{"rec2020", "Utility - Rec.2020 - Camera",
                                                 "Rec.2020 - Camera", "rec2020_camera"};
  OCIO::ConstConfigRcPtr config = configFor(configPath);
  for (const char* name : primaries == "bt2020" ? kRec2020 : kRec709)
    if (OCIO::ConstColorSpaceRcPtr space = config->getColorSpace(name)) return space->getName();
  return std::nullopt;
}

struct ColorConverter::Impl {
  Conversion conversion;
  bool noOp = false;
};

ColorConverter::ColorConverter(const std::string& from, const std::string& to,
                               const std::string& configPath)
    : impl_(std::make_unique<Impl>()) {
  OCIO::ConstConfigRcPtr config = configFor(configPath);
  const std::string fromName = resolveName(config, from, configPath);
  const std::string toName = resolveName(config, to, configPath);
  if (fromName == toName) {
    impl_->noOp = true;
    return;
  }
  impl_->conversion = conversionFor(config, chosenConfigPath(configPath), fromName, toName);
  impl_->noOp = impl_->conversion.processor->isNoOp();
}

ColorConverter::~ColorConverter() = default;
ColorConverter::ColorConverter(ColorConverter&&) noexcept = default;
ColorConverter& ColorConverter::operator=(ColorConverter&&) noexcept = default;

bool ColorConverter::isNoOp() const {
  return impl_->noOp;
}

void ColorConverter::apply(Image& image) const {
  if (impl_->noOp || image.empty()) return;
  const Conversion& conversion = impl_->conversion;
  const ptrdiff_t pixelBytes = 4 * sizeof(float);
  try {
    forEachBlock(size_t(image.height), kMinRowsPerBand, [&](size_t firstRow, size_t endRow) {
      const size_t firstPixel = firstRow * image.width;
      const size_t pixels = (endRow - firstRow) * image.width;
      if (conversion.lut) {
        conversion.lut->apply(image.rgba.data() + firstPixel * 4, pixels);
        return;
      }
      // RGB only, read with the RGBA buffer's strides: OCIO never sees (or changes) alpha.
      OCIO::PackedImageDesc rgb(image.rgba.data() + firstPixel * 4, image.width,
                                static_cast<long>(endRow - firstRow), OCIO::CHANNEL_ORDERING_RGB,
                                OCIO::BIT_DEPTH_F32, sizeof(float), pixelBytes,
                                pixelBytes * image.width);
      conversion.processor->apply(rgb);
    });
  } catch (const OCIO::Exception& e) {
    throw Error(std::string("colour conversion failed: ") + e.what(), {"color", {}, ""});
  }
}

std::optional<CodeValues> ColorConverter::codeValues(int bits) const {
  if ((bits != 8 && bits != 16) || (!impl_->noOp && !impl_->conversion.lut)) return std::nullopt;
  const int codes = 1 << bits;
  // Each code's value as the readers make it (codeScale).
  const float scale = codeScale(bits);
  Image ramp(codes, 1);
  for (int k = 0; k < codes; ++k)
    for (int c = 0; c < 3; ++c)
      ramp.rgba[size_t(k) * 4 + size_t(c)] = static_cast<float>(k) * scale;
  // Every code lies in the table (no pixel through the exact path, which takes a pixel's three
  // channels together): each channel's value is then its own.
  if (!impl_->noOp && impl_->conversion.lut->apply(ramp.rgba.data(), size_t(codes)) != 0)
    return std::nullopt;
  CodeValues values;
  for (int c = 0; c < 3; ++c) {
    values[size_t(c)].resize(size_t(codes));
    for (int k = 0; k < codes; ++k)
      values[size_t(c)][size_t(k)] = ramp.rgba[size_t(k) * 4 + size_t(c)];
  }
  return values;
}

std::vector<std::string> colorSpaceNames(const std::string& configPath) {
  return namesIn(configFor(configPath));
}

std::string colorLibraryVersion() {
  return OCIO::GetVersion();
}

void saveBuiltinConfig(const std::string& path) {
  std::ostringstream text;
  configFor("")->serialize(text);
  fs::writeTextFile(path, text.str());
}

}  // namespace pluvia
