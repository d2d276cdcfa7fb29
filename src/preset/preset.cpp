#include "preset/preset.h"

#include <unistd.h>
#include <algorithm>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "pluvia/version.h"
#include "preset/dotted_path.h"
#include "preset/json_text.h"
#include "preset/ramp.h"
#include "util/executable.h"
#include "util/fs.h"
#include "util/hash.h"
#include "util/printable.h"

namespace pluvia {
namespace stdfs = std::filesystem;
using nlohmann::json;

namespace {

std::string joinLines(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += "\n  " + l;
  return text;
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
    text = fs::readInputText(file, "the preset");
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
    : Error(source == kSetSource ? fmt::format("invalid --set:{}", joinLines(problems))
                                 : fmt::format("invalid preset {}:{}", source, joinLines(problems)),
            source == kSetSource ? ErrorContext{"preset"} : ErrorContext{"preset", {}, source}),
      problems_(std::move(problems)),
      commandLine_(source == kSetSource) {}

namespace {

stdfs::path& presetFolder() {
  static stdfs::path folder;
  return folder;
}

}  // namespace

void setPresetFolder(const stdfs::path& folder) {
  presetFolder() = folder;
}

std::vector<stdfs::path> presetSearchPath() {
  return shippedDataFolders(presetFolder(), "presets", kSourcePresetDir);
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
  std::error_code ec;  // a name too long for a file name is looked for as a name, not thrown on
  if (stdfs::is_regular_file(asPath, ec)) return asPath;
  bool looksLikePath = nameOrPath.find('/') != std::string::npos || asPath.extension() == ".json";
  if (!looksLikePath) {
    for (const auto& dir : presetSearchPath()) {
      stdfs::path candidate = dir / (nameOrPath + ".json");
      if (stdfs::is_regular_file(candidate, ec)) return candidate;
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
    throw PresetError(
        kSetSource,
        {fmt::format("'{}' is not KEY=VALUE (for example rain.rate_mm_h=40)", assignment)});
  }
  std::string key = assignment.substr(0, eq);
  std::string text = assignment.substr(eq + 1);
  if (!isValidUtf8(assignment)) {
    throw PresetError(kSetSource, {"a --set line is not valid UTF-8 text"});
  }
  if (key == "extends") {
    throw PresetError(kSetSource, {"extends cannot be set on the command line: give that preset "
                                   "with -p, or write a preset file that extends it"});
  }
  try {
    checkJsonNesting(text, "--set");
  } catch (const PresetError& e) {
    throw PresetError(kSetSource, {fmt::format("--set {}: {}", key, e.problems().front())});
  }
  json value;
  try {
    value = json::parse(text);
  } catch (const json::parse_error&) {
    value = text;
  } catch (const json::exception&) {
    throw PresetError(kSetSource, {fmt::format("{}: {} is too large for a number", key, text)});
  }
  json* node = &document;
  auto parts = splitDots(key);
  for (const std::string& part : parts)
    if (part.empty())
      throw PresetError(kSetSource, {fmt::format("--set {}: an empty key between dots (write "
                                                 "section.key, for example rain.rate_mm_h)",
                                                 key)});
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    bool last = i + 1 == parts.size();
    if (node->is_array() && isIndex(part)) {
      const size_t index = indexValue(part);
      if (index >= node->size())
        throw PresetError(kSetSource, {fmt::format("{}: index {} is past the end of a list of {}",
                                                   key, part, node->size())});
      node = &(*node)[index];
    } else if (node->is_object() || node->is_null()) {
      if (last) {
        (*node)[part] = value;
        return;
      }
      if (!node->contains(part)) (*node)[part] = json::object();
      node = &(*node)[part];
    } else {
      throw PresetError(kSetSource, {fmt::format("{}: '{}' is not an object", key, part)});
    }
    if (last) *node = value;
  }
}

void fillDefaults(json& document, const Schema& schema) {
  for (const auto& section : schema) {
    if (!document.contains(section.name)) document[section.name] = json::object();
    setDefaults(document[section.name], section.params);
  }
}

namespace {

// Each path parameter's value made absolute with links resolved (ParamSpec::path): relative
// paths are read from the current folder, so that is where they start.
void canonicalizePaths(json& document, const Schema& schema) {
  for (const auto& section : schema)
    for (const ParamSpec& param : section.params) {
      if (!param.path || !document[section.name].contains(param.key)) continue;
      json& value = document[section.name][param.key];
      if (!value.is_string()) continue;
      const std::string text = value.get<std::string>();
      if (text.empty() || text.rfind("ocio://", 0) == 0 ||
          std::find(param.choices.begin(), param.choices.end(), text) != param.choices.end())
        continue;
      value = fs::canonicalSpelling(text).string();
    }
}

}  // namespace

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
  if (!setProblems.empty()) throw PresetError(kSetSource, setProblems);
  wrapKeyShorthand(document,
                   schema);  // problems name the full form's paths (/rain/rate_mm_h/keys/1/1)
  // A problem at or under a key a --set wrote is that --set's, the argument named; the others
  // are the file's. Every problem is said at once; only when the file has none is it the command
  // line's mistake alone (exit 2).
  std::vector<std::string> fileProblems;
  for (const std::string& problem : validatePreset(document, schema)) {
    const std::string* blamed = nullptr;
    for (const std::string& assignment : overrides) {
      const std::string key = "/" + assignment.substr(0, assignment.find('='));
      std::string pointer = key;
      std::replace(pointer.begin(), pointer.end(), '.', '/');
      if (problem.rfind(pointer, 0) == 0 &&
          (problem.size() == pointer.size() || problem[pointer.size()] == '/' ||
           problem[pointer.size()] == ':'))
        blamed = &assignment;
    }
    if (blamed)
      setProblems.push_back("--set " + printable(*blamed) + ": " + problem);
    else
      fileProblems.push_back(problem);
  }
  if (!fileProblems.empty()) {
    fileProblems.insert(fileProblems.end(), setProblems.begin(), setProblems.end());
    throw PresetError(file.string(), fileProblems);
  }
  if (!setProblems.empty()) throw PresetError(kSetSource, setProblems);
  fillDefaults(document, schema);
  canonicalizePaths(document, schema);
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
