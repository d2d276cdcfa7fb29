#pragma once
// Presets: JSON files with a schema version ("pluvia": 1), "extends" (a shipped preset name or a
// path) and sections validated against the Schema. `--set key.path=value` overrides any key.
// Validation reports every problem at once, each naming its JSON Pointer path; nothing is
// rendered from an invalid preset.
//
// Number and Integer section parameters marked keyframable may be keyframed over clip frame
// numbers (preset/ramp.h; `pluvia describe` shows them as number|keys):
//   "rate_mm_h": {"keys": [[0, 0], [48, 40]], "interpolation": "linear"}   (or "smooth", "hold")
// and `--set rain.rate_mm_h=[[0,0],[48,40]]` is shorthand for {"keys": [[0,0],[48,40]]}.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "preset/param_table.h"
#include "preset/ramp.h"
#include "util/error.h"

namespace pluvia {

inline constexpr int kPresetSchemaVersion = 1;

// The source of problems in --set arguments rather than in a preset file.
inline constexpr const char* kSetSource = "--set";

// All the problems found in a preset, one line each; from `source` kSetSource, each names its
// --set argument, and they are the command line's mistakes (a usage error, exit 2).
class PresetError : public Error {
 public:
  PresetError(const std::string& source, std::vector<std::string> problems);
  const std::vector<std::string>& problems() const { return problems_; }
  bool isCommandLine() const { return commandLine_; }

 private:
  std::vector<std::string> problems_;
  bool commandLine_ = false;
};

// A folder searched for preset names before the others (the front end sets it from
// $PLUVIA_PRESET_DIR, cli/process_variables.h, before any work); empty: none.
void setPresetFolder(const std::filesystem::path& folder);
// Folders searched for preset names: that folder, presets/ beside the binary's parent, and the
// source tree's presets/.
std::vector<std::filesystem::path> presetSearchPath();
// Names of the shipped presets (files NAME.json in the search path).
std::vector<std::string> shippedPresetNames();
// A name or path -> the file. Throws PresetError naming what was looked for.
std::filesystem::path findPreset(const std::string& nameOrPath);

class Preset {
 public:
  // Loads, follows "extends", applies the overrides ("rain.rate_mm_h=40"), validates against the
  // schema and fills defaults. Throws PresetError listing every problem.
  static Preset resolve(const std::string& nameOrPath, const std::vector<std::string>& overrides,
                        const Schema& schema);

  const nlohmann::json& json() const { return resolved_; }
  const std::string& source() const { return source_; }
  std::string hash() const;  // 16 hex digits of the resolved JSON

  // Typed access by dotted path ("rain.wind.speed_m_s"); the value exists after resolve().
  const nlohmann::json& at(const std::string& dottedPath) const;
  // A plain number, or for a keyframed value the value at its first key (what a consumer that
  // does not animate the parameter sees).
  double number(const std::string& dottedPath) const;
  // The value at clip frame `frame` (fractional frames interpolate); a plain number whatever the
  // frame.
  double number(const std::string& dottedPath, double frame) const;
  // The value as a Ramp (a constant for a plain number).
  Ramp ramp(const std::string& dottedPath) const;
  bool boolean(const std::string& dottedPath) const;
  std::string string(const std::string& dottedPath) const;
  std::array<float, 3> color(const std::string& dottedPath) const;
  bool has(const std::string& dottedPath) const;

 private:
  nlohmann::json resolved_;
  std::string source_;
};

// Applies one "a.b.c=value" override to a JSON document; the value is parsed as JSON when it
// parses (numbers, true, [1,2,3]) and taken as a string otherwise. Throws PresetError when the
// text has no '=' or the path walks through a non-object.
void applyOverride(nlohmann::json& document, const std::string& assignment);

// Checks a merged preset document against the schema; returns every problem found.
std::vector<std::string> validatePreset(const nlohmann::json& document, const Schema& schema);

// Fills every missing key with its default (objects created as needed) and writes keyframes in
// their full form ({"keys": [...], "interpolation": "linear"} for a bare list of pairs).
void fillDefaults(nlohmann::json& document, const Schema& schema);

}  // namespace pluvia
