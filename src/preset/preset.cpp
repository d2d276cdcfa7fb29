#include "preset/preset.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "pluvia/version.h"
#include "preset/json_text.h"
#include "preset/ramp.h"
#include "util/executable.h"
#include "util/fs.h"
#include "util/hash.h"

namespace pluvia {
namespace stdfs = std::filesystem;
using nlohmann::json;

namespace {

std::string joinLines(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += "\n  " + l;
  return text;
}

std::vector<std::string> splitDots(const std::string& path) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    size_t dot = path.find('.', start);
    parts.push_back(path.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

bool isIndex(const std::string& s) {
  return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
}

// A list index as written in a dotted path; indexes past any list's size (and past what a
// size_t holds) are all the same: out of range.
size_t indexValue(const std::string& s) {
  constexpr size_t kBeyondAnyList = std::numeric_limits<size_t>::max();
  return s.size() > 9 ? kBeyondAnyList : std::stoul(s);
}

// Deep merge: objects merge key by key, anything else in `over` replaces `base`.
void mergeInto(json& base, const json& over) {
  for (auto it = over.begin(); it != over.end(); ++it) {
    if (it.value().is_object() && base.contains(it.key()) && base[it.key()].is_object()) {
      mergeInto(base[it.key()], it.value());
    } else {
      base[it.key()] = it.value();
    }
  }
}

// Deeper than any real chain of looks (base, a show's, a sequence's, a shot's ...): a longer one
// was made by a script gone wrong, and following it would exhaust the stack.
constexpr size_t kMaxExtendsDepth = 64;

json loadWithExtends(const stdfs::path& file, std::vector<std::string>& chain) {
  if (chain.size() >= kMaxExtendsDepth)
    throw PresetError(file.string(),
                      {fmt::format("\"extends\" chains more than {} presets (from {})",
                                   kMaxExtendsDepth, chain.front())});
  std::string canonical = stdfs::weakly_canonical(file).string();
  for (const auto& c : chain) {
    if (c == canonical)
      throw PresetError(file.string(), {"\"extends\" forms a cycle through " + canonical});
  }
  chain.push_back(canonical);
  std::string text;
  try {
    text = fs::readTextFile(file);
  } catch (const Error& e) {
    throw PresetError(file.string(), {e.what()});
  }
  json document = parsePresetJson(text, file.string());
  if (!document.is_object())
    throw PresetError(file.string(), {"/: a preset must be a JSON object"});
  if (document.contains("extends")) {
    if (!document["extends"].is_string())
      throw PresetError(file.string(), {"/extends: must be a preset name or path"});
    std::string parentName = document["extends"];
    stdfs::path parent = file.parent_path() / parentName;
    if (!stdfs::is_regular_file(parent)) parent = findPreset(parentName);
    json base = loadWithExtends(parent, chain);
    document.erase("extends");
    mergeInto(base, document);
    return base;
  }
  return document;
}

std::string pointer(const std::string& parent, const std::string& key) {
  return parent + "/" + key;
}

std::string numberText(double v) {
  return fmt::format("{:g}", v);
}

// No number may be larger than this, whatever its range: a ramp between keys at -1e308 and
// 1e308 overflowed (their difference is Inf). Above 2^53 doubles skip integers anyway.
constexpr double kMaxNumberMagnitude = 1e15;
// The largest value a half float (EXR output) holds; a larger colour became Inf pixels.
constexpr double kMaxHalf = 65504.0;

double lowestAllowed(const ParamSpec& spec) {
  return std::max(spec.minValue, -kMaxNumberMagnitude);
}
double highestAllowed(const ParamSpec& spec) {
  return std::min(spec.maxValue, kMaxNumberMagnitude);
}

// The section's value at a dotted key, or its default; nullptr when it has neither.
const json* valueOrDefault(const SectionSpec& section, const json& object, const std::string& key) {
  const json* node = &object;
  for (const auto& part : splitDots(key)) {
    node = node->is_object() && node->contains(part) ? &(*node)[part] : nullptr;
    if (!node) break;
  }
  if (node) return node;
  const ParamSpec* spec = section.find(key);
  return spec ? &spec->defaultValue : nullptr;
}

void checkIncreasing(const SectionSpec& section, const json& object,
                     std::vector<std::string>& problems) {
  for (const auto& [lower, upper] : section.increasing) {
    const json* a = valueOrDefault(section, object, lower);
    const json* b = valueOrDefault(section, object, upper);
    if (!a || !b || !a->is_number() || !b->is_number()) continue;  // reported by the type check
    if (!(a->get<double>() < b->get<double>())) {
      problems.push_back(fmt::format("/{0}/{1} ({2}) must be less than /{0}/{3} ({4})",
                                     section.name, lower, a->dump(), upper, b->dump()));
    }
  }
}

// Where keyframes may appear. Section: a keyframable number may be keys and any other number given
// as keys is told it is fixed over the shot. Item: list item fields, where a keyframable field may
// be keys and any other is checked as a plain value ("expected a number"). None: inside keys.
enum class KeyMode { None, Section, Item };

void checkValue(const ParamSpec& spec, const json& value, const std::string& where,
                std::vector<std::string>& problems, KeyMode keyMode);

bool isNumeric(const ParamSpec& spec) {
  return spec.type == ParamType::Number || spec.type == ParamType::Integer;
}

void checkObjectFields(const std::vector<ParamSpec>& params, const json& object,
                       const std::string& where, const std::string& prefix,
                       std::vector<std::string>& problems, KeyMode keyMode,
                       const std::set<std::string>& extraKeys = {}) {
  for (auto it = object.begin(); it != object.end(); ++it) {
    const std::string key = prefix.empty() ? it.key() : prefix + "." + it.key();
    const std::string path = pointer(where, it.key());
    if (extraKeys.count(it.key())) continue;
    const ParamSpec* spec = nullptr;
    bool isPrefix = false;
    std::vector<std::string> siblings;
    for (const auto& p : params) {
      if (p.key == key) spec = &p;
      if (p.key.rfind(key + ".", 0) == 0) isPrefix = true;
      // Candidate names at this nesting level, for the suggestion.
      if (prefix.empty() || p.key.rfind(prefix + ".", 0) == 0) {
        std::string rest = prefix.empty() ? p.key : p.key.substr(prefix.size() + 1);
        siblings.push_back(rest.substr(0, rest.find('.')));
      }
    }
    if (spec) {
      checkValue(*spec, it.value(), path, problems, keyMode);
    } else if (isPrefix) {
      if (!it.value().is_object()) {
        problems.push_back(fmt::format("{}: expected an object, got {}", path, it.value().dump()));
      } else {
        checkObjectFields(params, it.value(), path, key, problems, keyMode);
      }
    } else {
      problems.push_back(
          fmt::format("{}: unknown key '{}'{}", path, it.key(), didYouMean(it.key(), siblings)));
    }
  }
}

// "<where>/<key>: unknown key '<key>' in <what>" for each key of `object` not in `allowed`.
void reportUnknownKeys(const json& object, const std::vector<std::string>& allowed,
                       const std::string& where, const std::string& what,
                       std::vector<std::string>& problems) {
  for (auto it = object.begin(); it != object.end(); ++it) {
    if (std::find(allowed.begin(), allowed.end(), it.key()) != allowed.end()) continue;
    problems.push_back(fmt::format("{}/{}: unknown key '{}' in {}{}", where, it.key(), it.key(),
                                   what, didYouMean(it.key(), allowed)));
  }
}

// A keyframed number: {"keys": [[frame, value], ...], "interpolation": "linear"} or the bare list
// of pairs. Each value is checked like a plain one, at its own path (/rain/rate_mm_h/keys/1/1).
void checkKeys(const ParamSpec& spec, const json& value, const std::string& where,
               std::vector<std::string>& problems) {
  const json* keys = &value;
  std::string keysWhere = where;
  if (value.is_object()) {
    reportUnknownKeys(value, {"keys", "interpolation"}, where, "keyframes", problems);
    if (value.contains("interpolation")) {
      RampInterpolation unused;
      const json& interpolation = value["interpolation"];
      if (!interpolation.is_string() ||
          !parseRampInterpolation(interpolation.get<std::string>(), unused)) {
        const std::vector<std::string> names = rampInterpolationNames();
        std::string nearest =
            interpolation.is_string() ? nearestWord(interpolation.get<std::string>(), names) : "";
        problems.push_back(fmt::format(
            "{}/interpolation: expected one of: {}{} (got {})", where, fmt::join(names, ", "),
            nearest.empty() ? "" : fmt::format(" (did you mean '{}'?)", nearest),
            interpolation.dump()));
      }
    }
    if (!value.contains("keys")) {
      problems.push_back(fmt::format(
          "{}/keys: missing; keyframes are {{\"keys\": [[frame, value], ...]}}", where));
      return;
    }
    keys = &value["keys"];
    keysWhere = where + "/keys";
  }
  if (!keys->is_array() || keys->empty()) {
    problems.push_back(
        fmt::format("{}: expected a list of at least one [frame, value] key (got {})", keysWhere,
                    keys->dump()));
    return;
  }
  double previousFrame = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < keys->size(); ++i) {
    const json& key = (*keys)[i];
    std::string keyWhere = fmt::format("{}/{}", keysWhere, i);
    if (!key.is_array() || key.size() != 2) {
      problems.push_back(fmt::format("{}: expected [frame, value] (got {})", keyWhere, key.dump()));
      continue;
    }
    if (!key[0].is_number() || !std::isfinite(key[0].get<double>()) ||
        std::fabs(key[0].get<double>()) > kMaxNumberMagnitude) {
      problems.push_back(fmt::format("{}/0: expected a frame number between -{} and {} (got {})",
                                     keyWhere, numberText(kMaxNumberMagnitude),
                                     numberText(kMaxNumberMagnitude), key[0].dump()));
    } else {
      double frame = key[0].get<double>();
      if (!(frame > previousFrame)) {
        problems.push_back(
            fmt::format("{}/0: key frames must increase strictly; key {} is at frame {} (got {})",
                        keyWhere, i - 1, numberText(previousFrame), key[0].dump()));
      }
      previousFrame = std::max(previousFrame, frame);
    }
    checkValue(spec, key[1], keyWhere + "/1", problems, KeyMode::None);
  }
}

// A polygon: [[x, y], ...] (at least 3 points), or keys [{"frame": F, "points": [...]}, ...] in
// strictly increasing frame order with the same number of points in each.
void checkPoints(const ParamSpec& spec, const json& value, const std::string& where,
                 std::vector<std::string>& problems) {
  const std::string shape =
      "expected [[x, y], ...] with at least 3 points, or keys [{\"frame\": F, \"points\": "
      "[[x, y], ...]}, ...]";
  // Returns the number of points, or 0 after reporting a problem.
  auto checkPolygon = [&](const json& points, const std::string& at) -> size_t {
    if (!points.is_array() || points.size() < 3) {
      problems.push_back(fmt::format("{}: {} (got {})", at, shape, points.dump()));
      return 0;
    }
    for (size_t i = 0; i < points.size(); ++i) {
      const json& p = points[i];
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
        problems.push_back(fmt::format("{}/{}: expected [x, y] (got {})", at, i, p.dump()));
        return 0;
      }
      for (const json& c : p) {
        const double v = c.get<double>();
        if (!std::isfinite(v) || v < spec.minValue || v > spec.maxValue) {
          problems.push_back(fmt::format("{}/{}: each must be between {} and {} (got {})", at, i,
                                         numberText(spec.minValue), numberText(spec.maxValue),
                                         p.dump()));
          return 0;
        }
      }
    }
    return points.size();
  };
  if (!value.is_array() || value.empty() || !value[0].is_object()) {
    checkPolygon(value, where);
    return;
  }
  double previousFrame = -std::numeric_limits<double>::infinity();
  size_t count = 0;
  for (size_t i = 0; i < value.size(); ++i) {
    const json& key = value[i];
    const std::string keyWhere = fmt::format("{}/{}", where, i);
    if (!key.is_object()) {
      problems.push_back(
          fmt::format("{}: expected {{\"frame\": F, \"points\": [[x, y], ...]}} (got {})", keyWhere,
                      key.dump()));
      continue;
    }
    reportUnknownKeys(key, {"frame", "points"}, keyWhere, "points keys", problems);
    if (!key.contains("frame") || !key["frame"].is_number() ||
        !std::isfinite(key["frame"].get<double>())) {
      problems.push_back(fmt::format("{}/frame: expected a frame number (got {})", keyWhere,
                                     key.value("frame", json()).dump()));
    } else {
      const double frame = key["frame"].get<double>();
      if (!(frame > previousFrame)) {
        problems.push_back(fmt::format(
            "{}/frame: key frames must increase strictly; key {} is at frame {} (got {})", keyWhere,
            i - 1, numberText(previousFrame), key["frame"].dump()));
      }
      previousFrame = std::max(previousFrame, frame);
    }
    if (!key.contains("points")) {
      problems.push_back(fmt::format("{}/points: missing", keyWhere));
      continue;
    }
    const size_t n = checkPolygon(key["points"], keyWhere + "/points");
    if (n && count && n != count) {
      problems.push_back(fmt::format(
          "{}/points: every key needs the same number of points (the first has {}, this one {})",
          keyWhere, count, n));
    }
    if (n && !count) count = n;
  }
}

void checkValue(const ParamSpec& spec, const json& value, const std::string& where,
                std::vector<std::string>& problems, KeyMode keyMode) {
  if (keyMode != KeyMode::None && spec.keyframes && (value.is_object() || value.is_array())) {
    return checkKeys(spec, value, where, problems);
  }
  if (keyMode == KeyMode::Section && isNumeric(spec) && Ramp::looksLikeKeys(value)) {
    problems.push_back(
        fmt::format("{}: cannot be keyframed, it is fixed over the shot; give one number", where));
    return;
  }
  auto bad = [&](const std::string& what) {
    problems.push_back(fmt::format("{}: {} (got {})", where, what, value.dump()));
  };
  auto checkRange = [&](double v) {
    if (!std::isfinite(v) || v < lowestAllowed(spec) || v > highestAllowed(spec)) {
      bad(fmt::format("must be between {} and {}{}", numberText(lowestAllowed(spec)),
                      numberText(highestAllowed(spec)),
                      spec.units.empty() ? "" : " " + spec.units));
    }
  };
  switch (spec.type) {
    case ParamType::Number:
      if (!value.is_number()) return bad("expected a number");
      checkRange(value.get<double>());
      return;
    case ParamType::Integer:
      if (!value.is_number_integer() &&
          !(value.is_number_float() && std::floor(value.get<double>()) == value.get<double>()))
        return bad("expected an integer");
      checkRange(value.get<double>());
      return;
    case ParamType::Boolean:
      if (!value.is_boolean()) bad("expected true or false");
      return;
    case ParamType::String:
      if (!value.is_string()) bad("expected a string");
      return;
    case ParamType::Enum: {
      std::string allowed;
      for (const auto& c : spec.choices) allowed += (allowed.empty() ? "" : ", ") + c;
      if (!value.is_string()) return bad("expected one of: " + allowed);
      std::string v = value.get<std::string>();
      if (std::find(spec.choices.begin(), spec.choices.end(), v) == spec.choices.end()) {
        bad("expected one of: " + allowed + didYouMean(v, spec.choices));
      }
      return;
    }
    case ParamType::Color3:
      if (!value.is_array() || value.size() != 3) return bad("expected [r, g, b]");
      for (const auto& c : value) {
        if (!c.is_number() || !std::isfinite(c.get<double>()) || c.get<double>() < 0 ||
            c.get<double>() > kMaxHalf)
          return bad("expected three numbers from 0 to 65504 (the largest a half float holds)");
      }
      return;
    case ParamType::Vector3:
      if (!value.is_array() || value.size() != 3) return bad("expected [x, y, z]");
      for (const auto& c : value) {
        if (!c.is_number()) return bad("expected three numbers");
      }
      for (const auto& c : value) {
        double v = c.get<double>();
        if (!std::isfinite(v) || v < lowestAllowed(spec) || v > highestAllowed(spec)) {
          return bad(fmt::format("each must be between {} and {}{}",
                                 numberText(lowestAllowed(spec)), numberText(highestAllowed(spec)),
                                 spec.units.empty() ? "" : " " + spec.units));
        }
      }
      return;
    case ParamType::Points2:
      return checkPoints(spec, value, where, problems);
    case ParamType::List: {
      if (!value.is_array()) return bad("expected a list");
      std::vector<std::string> types;
      for (const auto& [t, fields] : spec.itemTypes) types.push_back(t);
      const bool untyped = spec.itemTypes.size() == 1 && spec.itemTypes.begin()->first.empty();
      double previousOrder = -std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < value.size(); ++i) {
        const json& item = value[i];
        std::string itemWhere = fmt::format("{}/{}", where, i);
        if (untyped) {
          if (!item.is_object()) {
            problems.push_back(
                fmt::format("{}: expected an object (got {})", itemWhere, item.dump()));
            continue;
          }
          const auto& fields = spec.itemTypes.begin()->second;
          checkObjectFields(fields, item, itemWhere, "", problems, KeyMode::Item);
          for (const auto& field : fields) {
            if (field.required && !item.contains(field.key))
              problems.push_back(
                  fmt::format("{}/{}: missing (each item needs it)", itemWhere, field.key));
          }
          if (!spec.orderedBy.empty() && item.contains(spec.orderedBy) &&
              item[spec.orderedBy].is_number()) {
            double order = item[spec.orderedBy].get<double>();
            if (!(order > previousOrder)) {
              problems.push_back(fmt::format(
                  "{}/{}: must increase strictly from item to item; item {} has {} (got {})",
                  itemWhere, spec.orderedBy, i - 1, numberText(previousOrder),
                  item[spec.orderedBy].dump()));
            }
            previousOrder = std::max(previousOrder, order);
          }
          continue;
        }
        if (!item.is_object() || !item.contains("type") || !item["type"].is_string()) {
          problems.push_back(fmt::format("{}: each item needs a \"type\" (one of: {})", itemWhere,
                                         fmt::format("{}", fmt::join(types, ", "))));
          continue;
        }
        auto found = spec.itemTypes.find(item["type"].get<std::string>());
        if (found == spec.itemTypes.end()) {
          problems.push_back(fmt::format("{}/type: unknown item type {} (one of: {}){}", itemWhere,
                                         item["type"].dump(), fmt::join(types, ", "),
                                         didYouMean(item["type"].get<std::string>(), types)));
          continue;
        }
        checkObjectFields(found->second, item, itemWhere, "", problems, KeyMode::Item, {"type"});
        for (const auto& field : found->second) {
          if (field.required && !item.contains(field.key))
            problems.push_back(fmt::format("{}/{}: missing (each \"{}\" item needs it)", itemWhere,
                                           field.key, found->first));
        }
      }
      return;
    }
  }
}

// Fills defaults and writes keyframes (of section parameters and list item fields) in full form:
// a bare [[frame, value], ...] becomes {"keys": [...], "interpolation": "linear"}.
void setDefaults(json& object, const std::vector<ParamSpec>& params) {
  for (const auto& p : params) {
    json* node = &object;
    auto parts = splitDots(p.key);
    for (size_t i = 0; i + 1 < parts.size(); ++i) {
      if (!node->contains(parts[i])) (*node)[parts[i]] = json::object();
      node = &(*node)[parts[i]];
    }
    if (!node->contains(parts.back())) {
      // An optional field without a default (depth_bottom_m) stays absent: a null would not
      // validate if the resolved preset were read back.
      if (p.defaultValue.is_null()) continue;
      (*node)[parts.back()] = p.defaultValue;
    }
    json& value = (*node)[parts.back()];
    if (p.keyframes && Ramp::looksLikeKeys(value)) {
      if (value.is_array()) value = json{{"keys", value}};
      if (!value.contains("interpolation")) value["interpolation"] = "linear";
    }
    if (p.type == ParamType::List && value.is_array()) {
      for (auto& item : value) {
        if (!item.is_object()) continue;
        auto found = p.itemTypes.find(item.value("type", ""));
        if (found != p.itemTypes.end()) setDefaults(item, found->second);
      }
    }
  }
}

// A bare list of [frame, value] pairs given for a section's number becomes {"keys": [...]}, so
// that later overrides can address rain.rate_mm_h.keys.1.1 or rain.rate_mm_h.interpolation.
void wrapKeyShorthand(json& document, const Schema& schema) {
  for (const auto& section : schema) {
    if (!document.contains(section.name) || !document[section.name].is_object()) continue;
    for (const auto& p : section.params) {
      if (!p.keyframes) continue;
      json* node = &document[section.name];
      for (const auto& part : splitDots(p.key)) {
        node = node->is_object() && node->contains(part) ? &(*node)[part] : nullptr;
        if (!node) break;
      }
      if (node && node->is_array() && Ramp::looksLikeKeys(*node)) *node = json{{"keys", *node}};
    }
  }
}

const json* walk(const json& document, const std::string& dottedPath) {
  const json* node = &document;
  for (const auto& part : splitDots(dottedPath)) {
    if (node->is_object() && node->contains(part)) {
      node = &(*node)[part];
    } else if (node->is_array() && isIndex(part) && indexValue(part) < node->size()) {
      node = &(*node)[indexValue(part)];
    } else {
      return nullptr;
    }
  }
  return node;
}

}  // namespace

PresetError::PresetError(const std::string& source, std::vector<std::string> problems)
    : Error(fmt::format("invalid preset {}:{}", source, joinLines(problems)),
            {"preset", {}, source}),
      problems_(std::move(problems)) {}

std::vector<stdfs::path> presetSearchPath() {
  std::vector<stdfs::path> dirs;
  if (const char* env = std::getenv("PLUVIA_PRESET_DIR")) dirs.emplace_back(env);
  stdfs::path exeDir = executablePath().parent_path();
  if (!exeDir.empty()) {
    dirs.push_back(exeDir.parent_path() / "presets");
    dirs.push_back(exeDir.parent_path() / "share" / "pluvia" / "presets");
  }
  dirs.emplace_back(kSourcePresetDir);
  return dirs;
}

std::vector<std::string> shippedPresetNames() {
  std::set<std::string> names;
  for (const auto& dir : presetSearchPath()) {
    std::error_code ec;
    for (const auto& entry : stdfs::directory_iterator(dir, ec)) {
      if (entry.path().extension() == ".json") names.insert(entry.path().stem().string());
    }
  }
  return {names.begin(), names.end()};
}

stdfs::path findPreset(const std::string& nameOrPath) {
  stdfs::path asPath(nameOrPath);
  if (stdfs::is_regular_file(asPath)) return asPath;
  bool looksLikePath = nameOrPath.find('/') != std::string::npos || asPath.extension() == ".json";
  if (!looksLikePath) {
    for (const auto& dir : presetSearchPath()) {
      stdfs::path candidate = dir / (nameOrPath + ".json");
      if (stdfs::is_regular_file(candidate)) return candidate;
    }
  }
  auto names = shippedPresetNames();
  std::string nearest = nearestWord(nameOrPath, names);
  throw PresetError(
      nameOrPath,
      {fmt::format("no preset file or shipped preset named '{}'{} (shipped: {})", nameOrPath,
                   nearest.empty() ? "" : fmt::format(", did you mean '{}'?", nearest),
                   fmt::join(names, ", "))});
}

void applyOverride(json& document, const std::string& assignment) {
  size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw PresetError("--set", {fmt::format("'{}' is not KEY=VALUE (for example rain.rate_mm_h=40)",
                                            assignment)});
  }
  std::string key = assignment.substr(0, eq);
  std::string text = assignment.substr(eq + 1);
  if (!isValidUtf8(assignment)) {
    throw PresetError("--set", {"a --set line is not valid UTF-8 text"});
  }
  if (key == "extends") {
    throw PresetError("--set", {"extends cannot be set on the command line: give that preset "
                                "with -p, or write a preset file that extends it"});
  }
  try {
    checkJsonNesting(text, "--set");
  } catch (const PresetError& e) {
    throw PresetError("--set", {fmt::format("--set {}: {}", key, e.problems().front())});
  }
  json value;
  try {
    value = json::parse(text);
  } catch (const json::parse_error&) {
    value = text;
  } catch (const json::exception&) {
    throw PresetError("--set", {fmt::format("{}: {} is too large for a number", key, text)});
  }
  json* node = &document;
  auto parts = splitDots(key);
  for (const std::string& part : parts)
    if (part.empty())
      throw PresetError("--set", {fmt::format("--set {}: an empty key between dots (write "
                                              "section.key, for example rain.rate_mm_h)",
                                              key)});
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    bool last = i + 1 == parts.size();
    if (node->is_array() && isIndex(part)) {
      const size_t index = indexValue(part);
      if (index >= node->size())
        throw PresetError("--set", {fmt::format("{}: index {} is past the end of a list of {}", key,
                                                part, node->size())});
      node = &(*node)[index];
    } else if (node->is_object() || node->is_null()) {
      if (last) {
        (*node)[part] = value;
        return;
      }
      if (!node->contains(part)) (*node)[part] = json::object();
      node = &(*node)[part];
    } else {
      throw PresetError("--set", {fmt::format("{}: '{}' is not an object", key, part)});
    }
    if (last) *node = value;
  }
}

std::vector<std::string> validatePreset(const json& document, const Schema& schema) {
  std::vector<std::string> problems;
  if (!document.contains("pluvia")) {
    problems.push_back(
        fmt::format("/pluvia: missing schema version (add \"pluvia\": {})", kPresetSchemaVersion));
  } else if (document["pluvia"] != kPresetSchemaVersion) {
    problems.push_back(
        fmt::format("/pluvia: schema version {} is not supported (this pluvia reads {})",
                    document["pluvia"].dump(), kPresetSchemaVersion));
  }
  std::vector<std::string> topKeys{"pluvia", "extends", "description"};
  for (const auto& s : schema) topKeys.push_back(s.name);
  for (auto it = document.begin(); it != document.end(); ++it) {
    const std::string& key = it.key();
    if (key == "pluvia" || key == "extends") continue;
    if (key == "description") {
      if (!it.value().is_string()) problems.push_back("/description: expected a string");
      continue;
    }
    auto section = std::find_if(schema.begin(), schema.end(),
                                [&](const SectionSpec& s) { return s.name == key; });
    if (section == schema.end()) {
      problems.push_back(
          fmt::format("/{}: unknown section '{}'{}", key, key, didYouMean(key, topKeys)));
      continue;
    }
    if (!it.value().is_object()) {
      problems.push_back(fmt::format("/{}: expected an object, got {}", key, it.value().dump()));
      continue;
    }
    checkObjectFields(section->params, it.value(), "/" + key, "", problems, KeyMode::Section);
    checkIncreasing(*section, it.value(), problems);
  }
  return problems;
}

void fillDefaults(json& document, const Schema& schema) {
  for (const auto& section : schema) {
    if (!document.contains(section.name)) document[section.name] = json::object();
    setDefaults(document[section.name], section.params);
  }
}

Preset Preset::resolve(const std::string& nameOrPath, const std::vector<std::string>& overrides,
                       const Schema& schema) {
  stdfs::path file = findPreset(nameOrPath);
  std::vector<std::string> chain;
  nlohmann::json document = loadWithExtends(file, chain);
  // A --set that cannot be applied is the command line's mistake, not the preset file's.
  std::vector<std::string> setProblems;
  for (const auto& assignment : overrides) {
    try {
      wrapKeyShorthand(document, schema);
      applyOverride(document, assignment);
    } catch (const PresetError& e) {
      setProblems.insert(setProblems.end(), e.problems().begin(), e.problems().end());
    }
  }
  if (!setProblems.empty()) throw PresetError("--set", setProblems);
  std::vector<std::string> problems;
  wrapKeyShorthand(document,
                   schema);  // problems name the full form's paths (/rain/rate_mm_h/keys/1/1)
  auto found = validatePreset(document, schema);
  problems.insert(problems.end(), found.begin(), found.end());
  if (!problems.empty()) throw PresetError(file.string(), problems);
  fillDefaults(document, schema);
  Preset preset;
  preset.resolved_ = std::move(document);
  preset.resolved_.erase("extends");
  preset.source_ = file.string();
  return preset;
}

std::string Preset::hash() const {
  return Hasher().add(resolved_.dump()).hex();
}

const nlohmann::json& Preset::at(const std::string& dottedPath) const {
  const nlohmann::json* node = walk(resolved_, dottedPath);
  if (!node) throw Error("preset has no key " + dottedPath, {"preset", {}, source_});
  return *node;
}

bool Preset::has(const std::string& dottedPath) const {
  return walk(resolved_, dottedPath) != nullptr;
}
double Preset::number(const std::string& p) const {
  const nlohmann::json& v = at(p);
  return v.is_number() ? v.get<double>() : ramp(p).firstValue();
}
double Preset::number(const std::string& p, double frame) const {
  const nlohmann::json& v = at(p);
  return v.is_number() ? v.get<double>() : ramp(p).valueAt(frame);
}
Ramp Preset::ramp(const std::string& p) const {
  try {
    return Ramp::fromJson(at(p));
  } catch (const Error& e) {
    throw Error(fmt::format("preset key {} is not a number or keyframes: {}", p, e.what()),
                {"preset", {}, source_});
  }
}
bool Preset::boolean(const std::string& p) const {
  return at(p).get<bool>();
}
std::string Preset::string(const std::string& p) const {
  return at(p).get<std::string>();
}
std::array<float, 3> Preset::color(const std::string& p) const {
  const nlohmann::json& v = at(p);
  return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
}

}  // namespace pluvia
