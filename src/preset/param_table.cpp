#include "preset/param_table.h"

#include <regex>

#include <algorithm>
#include <cmath>
#include <regex>
#include <stdexcept>

#include <fmt/format.h>

namespace pluvia {

const char* paramTypeName(ParamType type) {
  switch (type) {
    case ParamType::Number:
      return "number";
    case ParamType::Integer:
      return "integer";
    case ParamType::Boolean:
      return "boolean";
    case ParamType::String:
      return "string";
    case ParamType::Enum:
      return "enum";
    case ParamType::Color3:
      return "rgb";
    case ParamType::List:
      return "list";
    case ParamType::Vector3:
      return "xyz";
    case ParamType::Points2:
      return "points";
  }
  return "?";
}

const ParamSpec* SectionSpec::find(const std::string& key) const {
  for (const auto& p : params)
    if (p.key == key) return &p;
  return nullptr;
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string nearestWord(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t bestDistance = std::numeric_limits<size_t>::max();
  for (const auto& c : candidates) {
    size_t d = editDistance(word, c);
    if (d < bestDistance) {
      bestDistance = d;
      best = c;
    }
  }
  // Accept up to about a third of the word's letters wrong, at least 2.
  if (bestDistance <= std::max<size_t>(2, word.size() / 3)) return best;
  // A key typed without its unit suffix ("sigma" for "sigma_px") is still a clear match.
  for (const auto& c : candidates)
    if (word.size() >= 3 && c.rfind(word, 0) == 0) return c;
  return "";
}

std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string nearest = nearestWord(word, candidates);
  return nearest.empty() ? "" : fmt::format(" (did you mean '{}'?)", nearest);
}

namespace {
std::string rangeText(const ParamSpec& p) {
  if (p.type == ParamType::Enum) {
    std::string s;
    for (const auto& c : p.choices) s += (s.empty() ? "" : "|") + c;
    return s;
  }
  if (p.type != ParamType::Number && p.type != ParamType::Integer && p.type != ParamType::Vector3 &&
      p.type != ParamType::Points2)
    return "";
  auto num = [](double v) {
    return std::isinf(v) ? std::string(v < 0 ? "-inf" : "inf") : fmt::format("{:g}", v);
  };
  return fmt::format("[{}, {}]", num(p.minValue), num(p.maxValue));
}

// Item fields count too, so that a section whose list items take keys (depth layers) explains
// the syntax.
bool isKeyframable(const ParamSpec& p) {
  if (p.keyframes) return true;
  for (const auto& [itemType, fields] : p.itemTypes)
    if (std::any_of(fields.begin(), fields.end(), isKeyframable)) return true;
  return false;
}

// " [NAME: value]" when the preset section `preset` sets the parameter to other than its default.
std::string presetValueText(const ParamSpec& p, const nlohmann::json* preset,
                            const std::string& presetName) {
  if (!preset) return "";
  const nlohmann::json::json_pointer at(
      fmt::format("/{}", std::regex_replace(p.key, std::regex("\\."), "/")));
  if (!preset->contains(at)) return "";
  const nlohmann::json& value = preset->at(at);
  if (value == p.defaultValue) return "";
  return fmt::format(" [{}: {}]", presetName, value.dump());
}

void describeParams(std::string& text, const std::vector<ParamSpec>& params,
                    const std::string& indent, const nlohmann::json* preset = nullptr,
                    const std::string& presetName = "") {
  for (const auto& p : params) {
    std::string type = paramTypeName(p.type);
    if (p.keyframes) type += "|keys";
    std::string defaultText = p.required                 ? "(required)"
                              : p.defaultValue.is_null() ? "-"
                                                         : p.defaultValue.dump();
    text += fmt::format("{}{:<22} {:<12} default {:<12} {:<16} {:<6} {}{}\n", indent, p.key, type,
                        defaultText, rangeText(p), p.units, p.help,
                        presetValueText(p, preset, presetName));
    if (!p.orderedBy.empty())
      text += fmt::format("{}  items in strictly increasing \"{}\"\n", indent, p.orderedBy);
    for (const auto& [itemType, fields] : p.itemTypes) {
      if (itemType.empty()) {
        text += fmt::format("{}  each item:\n", indent);
      } else {
        text += fmt::format("{}  item type \"{}\":\n", indent, itemType);
      }
      describeParams(text, fields, indent + "    ");
    }
  }
}
}  // namespace

std::string describeSection(const SectionSpec& section, const nlohmann::json* preset,
                            const std::string& presetName) {
  std::string text = fmt::format("{}: {}\n", section.name, section.help);
  if (!section.inputs.empty() || !section.outputs.empty()) {
    auto join = [](const std::vector<std::string>& v) {
      std::string s;
      for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
      return s.empty() ? std::string("-") : s;
    };
    text += fmt::format("  reads: {}   writes: {}\n", join(section.inputs), join(section.outputs));
  }
  describeParams(text, section.params, "  ", preset, presetName);
  if (std::any_of(section.params.begin(), section.params.end(), isKeyframable)) {
    text +=
        "  number|keys: a number, or keyframes over clip frames: "
        "{\"keys\": [[frame, value], ...], \"interpolation\": \"linear|smooth|hold\"}\n";
  }
  return text;
}

namespace {

// The fields every row has; the builders below set the rest.
ParamSpec row(std::string key, ParamType type, nlohmann::json defaultValue, std::string help) {
  ParamSpec p;
  p.key = std::move(key);
  p.type = type;
  p.defaultValue = std::move(defaultValue);
  p.help = std::move(help);
  return p;
}

ParamSpec rangedRow(std::string key, ParamType type, nlohmann::json defaultValue, NumberRange range,
                    std::string units, std::string help) {
  ParamSpec p = row(std::move(key), type, std::move(defaultValue), std::move(help));
  p.minValue = range.min;
  p.maxValue = range.max;
  p.units = std::move(units);
  return p;
}

}  // namespace

ParamSpec numberParam(std::string key, double defaultValue, NumberRange range, std::string units,
                      std::string help) {
  return rangedRow(std::move(key), ParamType::Number, defaultValue, range, std::move(units),
                   std::move(help));
}

ParamSpec integerParam(std::string key, int64_t defaultValue, NumberRange range, std::string units,
                       std::string help) {
  return rangedRow(std::move(key), ParamType::Integer, defaultValue, range, std::move(units),
                   std::move(help));
}

ParamSpec fractionParam(std::string key, double defaultValue, std::string help) {
  return numberParam(std::move(key), defaultValue, {0.0, 1.0}, "", std::move(help));
}

ParamSpec booleanParam(std::string key, bool defaultValue, std::string help) {
  return row(std::move(key), ParamType::Boolean, defaultValue, std::move(help));
}

ParamSpec enabledParam(std::string help) {
  return booleanParam("enabled", true, std::move(help));
}

ParamSpec stringParam(std::string key, std::string defaultValue, std::string help) {
  return row(std::move(key), ParamType::String, std::move(defaultValue), std::move(help));
}

ParamSpec pathParam(std::string key, std::string defaultValue, std::string help,
                    std::vector<std::string> words) {
  ParamSpec p = stringParam(std::move(key), std::move(defaultValue), std::move(help));
  p.path = true;
  p.choices = std::move(words);
  return p;
}

ParamSpec enumParam(std::string key, std::string defaultValue, std::vector<std::string> choices,
                    std::string help) {
  ParamSpec p = row(std::move(key), ParamType::Enum, std::move(defaultValue), std::move(help));
  p.choices = std::move(choices);
  return p;
}

ParamSpec colorParam(std::string key, nlohmann::json defaultValue, std::string units,
                     std::string help) {
  ParamSpec p = row(std::move(key), ParamType::Color3, std::move(defaultValue), std::move(help));
  p.units = std::move(units);
  return p;
}

ParamSpec vectorParam(std::string key, NumberRange range, std::string units, std::string help) {
  return rangedRow(std::move(key), ParamType::Vector3, nullptr, range, std::move(units),
                   std::move(help));
}

ParamSpec pointsParam(std::string key, NumberRange range, std::string help) {
  return rangedRow(std::move(key), ParamType::Points2, nullptr, range, "", std::move(help));
}

ParamSpec listParam(std::string key, nlohmann::json defaultValue,
                    std::map<std::string, std::vector<ParamSpec>> itemTypes, std::string help) {
  ParamSpec p = row(std::move(key), ParamType::List, std::move(defaultValue), std::move(help));
  p.itemTypes = std::move(itemTypes);
  return p;
}

ParamSpec required(ParamSpec field) {
  field.required = true;
  return withoutDefault(std::move(field));
}

ParamSpec withoutDefault(ParamSpec field) {
  field.defaultValue = nullptr;
  return field;
}

void allowKeyframes(std::vector<ParamSpec>& params, const std::vector<std::string>& keys) {
  for (const auto& key : keys) {
    auto it = std::find_if(params.begin(), params.end(),
                           [&](const ParamSpec& p) { return p.key == key; });
    if (it == params.end() || (it->type != ParamType::Number && it->type != ParamType::Integer))
      throw std::logic_error("allowKeyframes: '" + key + "' is not a number parameter");
    it->keyframes = true;
  }
}

}  // namespace pluvia
