#include "rain/stroke_library.h"

#include <cstdlib>
#include <filesystem>

#include <fmt/format.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "pluvia/version.h"
#include "util/error.h"
#include "util/executable.h"
#include "util/fs.h"
#include "util/input_guard.h"

namespace pluvia::rain {
namespace {

namespace stdfs = std::filesystem;

constexpr int kFormatVersion = 1;
constexpr double kQuantum = 65535.0;  // 16-bit PNG: alpha 1 is 65535

Error libraryError(const std::string& path, const std::string& what) {
  return Error(fmt::format("stroke library {}: {}", path, what), {"strokes", {}, path});
}

// The atlas rectangle of a stroke is inside the atlas and not empty.
bool rectInside(int x, int y, int w, int h, int width, int height) {
  return x >= 0 && y >= 0 && w > 0 && h > 0 && x + w <= width && y + h <= height;
}

void checkAtlasShape(const StrokeAtlas& atlas, const std::string& path) {
  if (atlas.width <= 0 || atlas.height <= 0 ||
      atlas.alpha.size() != size_t(atlas.width) * size_t(atlas.height)) {
    throw libraryError(path, fmt::format("atlas of {}x{} pixels holds {} values", atlas.width,
                                         atlas.height, atlas.alpha.size()));
  }
}

template <typename T>
T required(const nlohmann::json& object, const char* key, const std::string& path,
           const std::string& where = "") {
  if (!object.is_object() || !object.contains(key)) {
    throw libraryError(path, fmt::format("{}missing key \"{}\"", where, key));
  }
  try {
    return object.at(key).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw libraryError(path, fmt::format("{}key \"{}\" has the wrong type ({})", where, key,
                                         object.at(key).type_name()));
  }
}

// The document with one key per line and one stroke per line (small diffs, easy to read).
std::string formatLibraryJson(const nlohmann::json& doc) {
  std::string text = "{\n";
  size_t i = 0;
  for (const auto& [key, value] : doc.items()) {
    text += "  " + nlohmann::json(key).dump() + ": ";
    if (key == "strokes") {
      text += "[\n";
      for (size_t s = 0; s < value.size(); ++s)
        text += "    " + value[s].dump() + (s + 1 < value.size() ? ",\n" : "\n");
      text += "  ]";
    } else {
      text += value.dump();
    }
    text += ++i < doc.size() ? ",\n" : "\n";
  }
  return text + "}\n";
}

}  // namespace

void saveStrokeLibrary(const StrokeLibrary& library, const std::string& jsonPath) {
  const StrokeAtlas& atlas = library.atlas;
  checkAtlasShape(atlas, jsonPath);
  if (library.strokes.empty()) throw libraryError(jsonPath, "no strokes to write");
  nlohmann::json strokes = nlohmann::json::array();
  for (size_t i = 0; i < library.strokes.size(); ++i) {
    const StrokeInfo& s = library.strokes[i];
    if (!rectInside(s.x, s.y, s.width, s.height, atlas.width, atlas.height)) {
      throw libraryError(
          jsonPath, fmt::format("stroke {}: rect [{}, {}, {}, {}] outside the {}x{} atlas", i, s.x,
                                s.y, s.width, s.height, atlas.width, atlas.height));
    }
    strokes.push_back({{"rect", {s.x, s.y, s.width, s.height}},
                       {"length_px", s.lengthPx},
                       {"width_px", s.widthPx},
                       {"contrast", s.contrast},
                       {"source_frame", s.sourceFrame},
                       {"score", s.score}});
  }

  const stdfs::path json(jsonPath);
  const stdfs::path png = json.parent_path() / (json.stem().string() + ".png");
  if (fs::samePath(json, png)) throw libraryError(jsonPath, "the library must not be named .png");
  const nlohmann::json doc = {{"pluvia_strokes", kFormatVersion},
                              {"atlas", png.filename().string()},
                              {"width", atlas.width},
                              {"height", atlas.height},
                              {"source", library.source},
                              {"command", library.command},
                              {"strokes", strokes}};

  cv::Mat image(atlas.height, atlas.width, CV_16UC1);
  for (int y = 0; y < atlas.height; ++y) {
    auto* row = image.ptr<uint16_t>(y);
    for (int x = 0; x < atlas.width; ++x) {
      const double a = std::clamp(double(atlas.alpha[size_t(y) * atlas.width + x]), 0.0, 1.0);
      row[x] = uint16_t(std::lround(a * kQuantum));
    }
  }
  fs::ensureParentFolder(json, fs::MakeFolders::LastLevel);
  const stdfs::path tmp = fs::temporaryPathFor(png);
  bool written = false;
  try {
    written = cv::imwrite(tmp.string(), image, {cv::IMWRITE_PNG_COMPRESSION, 9});
  } catch (const cv::Exception&) {
    written = false;
  }
  if (!written) {
    std::error_code ec;
    stdfs::remove(tmp, ec);
    throw Error(fmt::format("cannot write the stroke atlas {}", png.string()),
                {"strokes", {}, png.string()});
  }
  fs::commitTemporary(tmp, png);
  // The JSON last: a library whose JSON exists always has its atlas beside it.
  fs::writeTextFile(json, formatLibraryJson(doc));
}

StrokeLibrary loadStrokeLibrary(const std::string& jsonPath) {
  const stdfs::path json(jsonPath);
  if (!stdfs::is_regular_file(json)) throw libraryError(jsonPath, "no such file");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(fs::readInputText(json, "the stroke library"));
  } catch (const nlohmann::json::parse_error& e) {
    // The position only: the parser's message quotes the file, which may be any file at all.
    throw libraryError(jsonPath, fmt::format("not valid JSON (at byte {})", e.byte));
  } catch (const nlohmann::json::exception&) {
    throw libraryError(jsonPath, "not valid JSON (a number too large for a double)");
  }
  if (!doc.is_object()) throw libraryError(jsonPath, "not a JSON object");
  const int version = required<int>(doc, "pluvia_strokes", jsonPath);
  if (version != kFormatVersion) {
    throw libraryError(
        jsonPath, fmt::format("format version {} (this pluvia reads {})", version, kFormatVersion));
  }

  StrokeLibrary library;
  if (doc.contains("source")) library.source = required<std::string>(doc, "source", jsonPath);
  if (doc.contains("command")) library.command = required<std::string>(doc, "command", jsonPath);
  const auto atlasName = required<std::string>(doc, "atlas", jsonPath);
  const int width = required<int>(doc, "width", jsonPath);
  const int height = required<int>(doc, "height", jsonPath);
  if (width <= 0 || height <= 0) {
    throw libraryError(jsonPath, fmt::format("atlas size {}x{} is empty", width, height));
  }
  const auto strokes = required<nlohmann::json>(doc, "strokes", jsonPath);
  if (!strokes.is_array()) throw libraryError(jsonPath, "key \"strokes\" is not an array");
  if (strokes.empty()) throw libraryError(jsonPath, "no strokes");

  for (size_t i = 0; i < strokes.size(); ++i) {
    const std::string where = fmt::format("stroke {}: ", i);
    const auto& entry = strokes[i];
    if (!entry.is_object()) throw libraryError(jsonPath, where + "not an object");
    const auto rect = required<std::vector<int>>(entry, "rect", jsonPath, where);
    if (rect.size() != 4) {
      throw libraryError(jsonPath, where + "\"rect\" must be [x, y, width, height]");
    }
    StrokeInfo s;
    s.x = rect[0], s.y = rect[1], s.width = rect[2], s.height = rect[3];
    if (!rectInside(s.x, s.y, s.width, s.height, width, height)) {
      throw libraryError(jsonPath, fmt::format("{}rect [{}, {}, {}, {}] outside the {}x{} atlas",
                                               where, s.x, s.y, s.width, s.height, width, height));
    }
    s.lengthPx = required<double>(entry, "length_px", jsonPath, where);
    s.widthPx = required<double>(entry, "width_px", jsonPath, where);
    s.contrast = required<double>(entry, "contrast", jsonPath, where);
    s.sourceFrame = required<int64_t>(entry, "source_frame", jsonPath, where);
    s.score = required<double>(entry, "score", jsonPath, where);
    library.strokes.push_back(s);
    library.atlas.rects.push_back(
        {float(s.x), float(s.y), float(s.x + s.width), float(s.y + s.height)});
  }

  const stdfs::path png = json.parent_path() / atlasName;
  if (!stdfs::is_regular_file(png)) {
    throw libraryError(jsonPath, fmt::format("atlas {} not found", png.string()));
  }
  cv::Mat image;
  try {
    fs::protectInputs({png.string()});
    image = cv::imread(png.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    image = cv::Mat();
  }
  if (image.empty()) {
    throw libraryError(jsonPath, fmt::format("cannot read the atlas {}", png.string()));
  }
  if (image.type() != CV_16UC1) {
    throw libraryError(jsonPath,
                       fmt::format("atlas {} is not a 16-bit grayscale PNG", png.string()));
  }
  if (image.cols != width || image.rows != height) {
    throw libraryError(jsonPath, fmt::format("atlas {} is {}x{}, the library says {}x{}",
                                             png.string(), image.cols, image.rows, width, height));
  }
  library.atlas.width = width;
  library.atlas.height = height;
  library.atlas.alpha.resize(size_t(width) * size_t(height));
  for (int y = 0; y < height; ++y) {
    const auto* row = image.ptr<uint16_t>(y);
    for (int x = 0; x < width; ++x) {
      library.atlas.alpha[size_t(y) * width + x] = float(row[x] / kQuantum);
    }
  }
  return library;
}

namespace {

stdfs::path& assetFolder() {
  static stdfs::path folder;
  return folder;
}

}  // namespace

void setAssetFolder(const stdfs::path& folder) {
  assetFolder() = folder;
}

std::string builtinStrokeLibraryPath() {
  // Searched as presets are: the asset folder set, assets/ beside the binary's parent (the source
  // tree for build/pluvia), an installed share/pluvia/assets, the configured source tree.
  const stdfs::path relative = stdfs::path("strokes") / "builtin.json";
  for (const auto& dir : shippedDataFolders(assetFolder(), "assets", kSourceAssetDir)) {
    if (stdfs::is_regular_file(dir / relative)) return (dir / relative).string();
  }
  // None there: the path loadStrokeLibrary will name in its error.
  return ((assetFolder().empty() ? stdfs::path(kSourceAssetDir) : assetFolder()) / relative)
      .string();
}

}  // namespace pluvia::rain
