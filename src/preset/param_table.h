#pragma once
// Parameters declared as data (FFmpeg AVOption style): one table drives validation, defaults,
// `pluvia describe` and the docs. A section is one top-level key of the preset ("rain", "fog").
// Number and Integer parameters of a section marked `keyframes` (the ones a stage reads frame by
// frame) also accept keyframes (see preset/ramp.h); every other value is fixed over the shot.
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace pluvia {

// Vector3: [x, y, z], three finite numbers, each within [minValue, maxValue].
// Points2: a polygon, [[x, y], ...] with at least 3 points, each coordinate within
// [minValue, maxValue]; or, to move it over frames, keys [{"frame": F, "points": [[x, y], ...]},
// ...] in strictly increasing frame order, each with the same number of points.
enum class ParamType { Number, Integer, Boolean, String, Enum, Color3, List, Vector3, Points2 };
const char* paramTypeName(ParamType type);

struct ParamSpec {
  std::string key;  // within its section, dotted for nested objects: "wind.speed_m_s"
  ParamType type = ParamType::Number;
  nlohmann::json defaultValue;
  double minValue = -std::numeric_limits<double>::infinity();
  double maxValue = std::numeric_limits<double>::infinity();
  std::vector<std::string> choices;  // Enum
  std::string units;                 // "mm/h", "m", "1/m", "px", "s", "deg"
  std::string help;
  // List: the fields allowed in an item, by the item's "type" value. Every item has "type",
  // except in a list whose only item type is "" (items of one kind, without "type").
  std::map<std::string, std::vector<ParamSpec>> itemTypes;
  // A field of a list item: the item must give it (it has no default).
  bool required = false;
  // List: the items must be in strictly increasing order of this Number field ("frame").
  std::string orderedBy = {};
  // Number or Integer parameter that may be keyframed over clip frames: a section parameter, or
  // a field of a list item (depth layers' distance_m); other item fields take plain numbers.
  bool keyframes = false;
  // String naming a file or folder (pathParam): the resolved preset holds it absolute, links
  // resolved, so that its hash and the resume identity do not depend on how it was spelled. The
  // words of `choices` (rain.strokes' "builtin") and "" are not paths.
  bool path = false;
};

// Builders for a table's rows, so that a table reads as named fields:
//   numberParam("rate_mm_h", 15.0, {0, 500}, "mm/h", "rain rate")
// A Number's default is stored as a JSON float and an Integer's as a JSON integer: the resolved
// preset (and so its hash and `pluvia describe`) writes them as given here.
struct NumberRange {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
};
ParamSpec numberParam(std::string key, double defaultValue, NumberRange range, std::string units,
                      std::string help);
ParamSpec integerParam(std::string key, int64_t defaultValue, NumberRange range, std::string units,
                       std::string help);
// A Number in [0, 1] without units: a fraction, a blend, a weight.
ParamSpec fractionParam(std::string key, double defaultValue, std::string help);
ParamSpec booleanParam(std::string key, bool defaultValue, std::string help);
// Every stage section's first row: "enabled", default true.
ParamSpec enabledParam(std::string help = "run this stage");
ParamSpec stringParam(std::string key, std::string defaultValue, std::string help);
// A String naming a file, a folder or a sequence pattern (see ParamSpec::path); `words` are
// values that name none ("builtin").
ParamSpec pathParam(std::string key, std::string defaultValue, std::string help,
                    std::vector<std::string> words = {});
ParamSpec enumParam(std::string key, std::string defaultValue, std::vector<std::string> choices,
                    std::string help);
// `defaultValue`: [r, g, b].
ParamSpec colorParam(std::string key, nlohmann::json defaultValue, std::string units,
                     std::string help);
// Vector3 and Points2 (see above), without a default.
ParamSpec vectorParam(std::string key, NumberRange range, std::string units, std::string help);
ParamSpec pointsParam(std::string key, NumberRange range, std::string help);
// A list whose items take the fields of their "type" (see ParamSpec::itemTypes).
ParamSpec listParam(std::string key, nlohmann::json defaultValue,
                    std::map<std::string, std::vector<ParamSpec>> itemTypes, std::string help);
// The same row for a field a list item must give: required, without a default.
ParamSpec required(ParamSpec field);
// The same row without a default (an optional field whose absence means something).
ParamSpec withoutDefault(ParamSpec field);

// Marks the named Number/Integer parameters as keyframable; throws std::logic_error for a key
// that is not one of them (a programming error in a stage's table).
void allowKeyframes(std::vector<ParamSpec>& params, const std::vector<std::string>& keys);

// Every member has an initializer, so that a designated initializer may leave any out.
struct SectionSpec {
  std::string name = {};  // top-level preset key
  std::string help = {};
  std::vector<std::string> inputs = {};   // artifacts read (pipeline stages only)
  std::vector<std::string> outputs = {};  // artifacts written
  std::vector<ParamSpec> params = {};
  // Pairs of Number keys whose values must increase, {"near_m", "far_m"}: near_m < far_m,
  // unless either is 0 (resolved from the shot).
  std::vector<std::pair<std::string, std::string>> increasing = {};
  const ParamSpec* find(const std::string& key) const;
};

using Schema = std::vector<SectionSpec>;

// Levenshtein distance, for "did you mean" suggestions.
size_t editDistance(const std::string& a, const std::string& b);
// The candidate nearest to `word`, or "" when none is reasonably close.
std::string nearestWord(const std::string& word, const std::vector<std::string>& candidates);
// " (did you mean 'x'?)" for the candidate nearest to `word`, or "" when none is close.
std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates);

// One line per parameter: key, type, default, range or choices, units, help. A keyframable
// parameter's type reads "number|keys" / "integer|keys". With `preset` (the section's object in a
// resolved preset) and its name, a parameter the preset sets to other than the default ends with
// "[NAME: value]".
std::string describeSection(const SectionSpec& section, const nlohmann::json* preset = nullptr,
                            const std::string& presetName = "");

}  // namespace pluvia
