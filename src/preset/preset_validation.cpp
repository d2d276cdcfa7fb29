// The preset schema check (validatePreset, preset.h): every section, key, type, range, choice,
// list item and keyframe of a document against the parameter tables, each problem named by its
// JSON pointer.
#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "preset/dotted_path.h"
#include "preset/param_table.h"
#include "preset/preset.h"
#include "preset/ramp.h"

namespace pluvia {
namespace {

using nlohmann::json;

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
    // 0 stands for a value resolved from the shot (rain.near_m from the lens, far_m from the
    // camera's resolution), which the stage keeps in order.
    if (a->get<double>() == 0.0 || b->get<double>() == 0.0) continue;
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

}  // namespace

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

}  // namespace pluvia
