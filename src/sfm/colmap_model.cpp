#include "sfm/colmap_model.h"

#include <optional>
#include <sstream>

#include "util/error.h"
#include "util/fs.h"
#include "util/parse_number.h"

namespace pluvia::sfm {
namespace {

const char* kStage = "sfm";

// Splits text into lines, skipping '#' comments (and blank lines unless keepBlank), keeping
// 1-based line numbers.
struct Line {
  int number = 0;
  std::string text;
};

std::vector<Line> dataLines(const std::string& text, bool keepBlank = false) {
  std::vector<Line> lines;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos ? !keepBlank : line[first] == '#') continue;
    lines.push_back({number, line});
  }
  return lines;
}

[[noreturn]] void fail(const std::string& fileName, int lineNumber, const std::string& what) {
  throw Error("COLMAP model " + fileName + " line " + std::to_string(lineNumber) + ": " + what,
              {kStage, std::nullopt, fileName});
}

// Reads every whitespace-separated field of a line as a number; fails naming the line when a field
// is not wholly a number.
std::vector<double> numbers(const std::string& text, const std::string& fileName, int lineNumber) {
  std::istringstream in(text);
  std::vector<double> values;
  std::string field;
  while (in >> field) {
    const std::optional<double> value = parseWholeNumber<double>(field);
    if (!value) fail(fileName, lineNumber, "'" + field + "' is not a number");
    values.push_back(*value);
  }
  return values;
}

int paramCount(const std::string& model) {
  static const std::map<std::string, int> counts = {
      {"SIMPLE_PINHOLE", 3}, {"PINHOLE", 4},
      {"SIMPLE_RADIAL", 4},  {"RADIAL", 5},
      {"OPENCV", 8},         {"OPENCV_FISHEYE", 8},
      {"FULL_OPENCV", 12},   {"SIMPLE_RADIAL_FISHEYE", 4},
      {"RADIAL_FISHEYE", 5}, {"THIN_PRISM_FISHEYE", 12}};
  auto it = counts.find(model);
  return it == counts.end() ? -1 : it->second;
}

// Models whose first two parameters are fx, fy (the rest start with a single f).
bool twoFocals(const std::string& model) {
  return model == "PINHOLE" || model == "OPENCV" || model == "OPENCV_FISHEYE" ||
         model == "FULL_OPENCV" || model == "THIN_PRISM_FISHEYE";
}

}  // namespace

double ColmapCamera::focalPx() const {
  if (paramCount(model) < 0 || static_cast<int>(params.size()) < paramCount(model))
    throw Error("COLMAP camera " + std::to_string(id) + ": unknown model " + model,
                {kStage, std::nullopt, ""});
  return twoFocals(model) ? 0.5 * (params[0] + params[1]) : params[0];
}

double ColmapCamera::cxPx() const {
  focalPx();  // validates the model
  return twoFocals(model) ? params[2] : params[1];
}

double ColmapCamera::cyPx() const {
  focalPx();
  return twoFocals(model) ? params[3] : params[2];
}

double ColmapModel::meanReprojectionErrorPx() const {
  double sum = 0.0;
  double count = 0.0;
  for (const auto& [id, point] : points) {
    double n = static_cast<double>(std::max<size_t>(point.track.size(), 1));
    sum += point.errorPx * n;
    count += n;
  }
  return count > 0.0 ? sum / count : 0.0;
}

void parseColmapCameras(const std::string& text, const std::string& fileName, ColmapModel& model) {
  for (const Line& line : dataLines(text)) {
    std::istringstream in(line.text);
    std::string idText, modelName, widthText, heightText;
    if (!(in >> idText >> modelName >> widthText >> heightText))
      fail(fileName, line.number, "expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
    ColmapCamera camera;
    std::vector<double> head =
        numbers(idText + " " + widthText + " " + heightText, fileName, line.number);
    camera.id = static_cast<int>(head[0]);
    camera.model = modelName;
    camera.width = static_cast<int>(head[1]);
    camera.height = static_cast<int>(head[2]);
    std::string rest;
    std::getline(in, rest);
    camera.params = numbers(rest, fileName, line.number);
    int expected = paramCount(modelName);
    if (expected < 0) fail(fileName, line.number, "unknown camera model " + modelName);
    if (static_cast<int>(camera.params.size()) != expected)
      fail(fileName, line.number,
           modelName + " needs " + std::to_string(expected) + " parameters, found " +
               std::to_string(camera.params.size()));
    if (camera.width <= 0 || camera.height <= 0)
      fail(fileName, line.number, "camera size must be positive");
    if (!model.cameras.emplace(camera.id, camera).second)
      fail(fileName, line.number, "duplicate camera id " + std::to_string(camera.id));
  }
}

void parseColmapImages(const std::string& text, const std::string& fileName, ColmapModel& model) {
  // Image records take two lines, and the second (the observations) is empty for an image without
  // keypoints, so blank lines matter here: only comments are skipped.
  std::vector<Line> lines = dataLines(text, /*keepBlank=*/true);
  // Strip trailing blank lines that would pair up as a bogus record.
  while (!lines.empty() && lines.back().text.find_first_not_of(" \t") == std::string::npos &&
         lines.size() % 2 == 1)
    lines.pop_back();
  for (size_t i = 0; i < lines.size(); i += 2) {
    const Line& head = lines[i];
    std::istringstream in(head.text);
    std::vector<std::string> fields;
    std::string field;
    while (in >> field) fields.push_back(field);
    if (fields.size() != 10)
      fail(fileName, head.number,
           "expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME, found " +
               std::to_string(fields.size()) + " fields");
    std::string numeric;
    for (int k = 0; k < 9; ++k) numeric += fields[k] + " ";
    std::vector<double> v = numbers(numeric, fileName, head.number);
    ColmapImage image;
    image.id = static_cast<int>(v[0]);
    image.qvec = Eigen::Quaterniond(v[1], v[2], v[3], v[4]);
    if (std::abs(image.qvec.norm() - 1.0) > 1e-3)
      fail(fileName, head.number, "quaternion is not unit length");
    image.tvec = Eigen::Vector3d(v[5], v[6], v[7]);
    image.cameraId = static_cast<int>(v[8]);
    image.name = fields[9];
    if (model.cameras.size() > 0 && model.cameras.count(image.cameraId) == 0)
      fail(fileName, head.number, "unknown camera id " + std::to_string(image.cameraId));
    if (i + 1 >= lines.size())
      fail(fileName, head.number, "image " + image.name + " has no observation line");
    const Line& obs = lines[i + 1];
    std::vector<double> o = numbers(obs.text, fileName, obs.number);
    if (o.size() % 3 != 0)
      fail(fileName, obs.number, "observations must be X Y POINT3D_ID triples");
    for (size_t k = 0; k < o.size(); k += 3)
      image.observations.push_back({{o[k], o[k + 1]}, static_cast<int64_t>(o[k + 2])});
    if (!model.images.emplace(image.id, std::move(image)).second)
      fail(fileName, head.number, "duplicate image id " + std::to_string(static_cast<int>(v[0])));
  }
}

void parseColmapPoints3D(const std::string& text, const std::string& fileName, ColmapModel& model) {
  for (const Line& line : dataLines(text)) {
    std::vector<double> v = numbers(line.text, fileName, line.number);
    if (v.size() < 8 || (v.size() - 8) % 2 != 0)
      fail(fileName, line.number,
           "expected POINT3D_ID X Y Z R G B ERROR followed by IMAGE_ID POINT2D_IDX pairs");
    ColmapPoint3D point;
    point.id = static_cast<int64_t>(v[0]);
    point.xyz = Eigen::Vector3d(v[1], v[2], v[3]);
    point.rgb =
        Eigen::Vector3i(static_cast<int>(v[4]), static_cast<int>(v[5]), static_cast<int>(v[6]));
    point.errorPx = v[7];
    for (size_t k = 8; k < v.size(); k += 2)
      point.track.push_back({static_cast<int>(v[k]), static_cast<int>(v[k + 1])});
    if (!model.points.emplace(point.id, std::move(point)).second)
      fail(fileName, line.number,
           "duplicate point id " + std::to_string(static_cast<int64_t>(v[0])));
  }
}

ColmapModel readColmapTextModel(const std::filesystem::path& folder) {
  ColmapModel model;
  auto read = [&](const char* name) {
    std::filesystem::path path = folder / name;
    if (!std::filesystem::exists(path))
      throw Error("COLMAP model file missing: " + path.string(), {kStage, std::nullopt, path});
    return fs::readInputText(path, "the COLMAP model file");
  };
  parseColmapCameras(read("cameras.txt"), (folder / "cameras.txt").string(), model);
  parseColmapImages(read("images.txt"), (folder / "images.txt").string(), model);
  parseColmapPoints3D(read("points3D.txt"), (folder / "points3D.txt").string(), model);
  return model;
}

}  // namespace pluvia::sfm
