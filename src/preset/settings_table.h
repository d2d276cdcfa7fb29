#pragma once
// A section's parameter table bound to its settings struct: one list of rows both declares the
// parameters (validation, defaults, `pluvia plan`, `pluvia describe`) and fills the struct.
//
//   const SettingsTable<SplashSettings> table(
//       {.name = "splash", .help = "...", .inputs = {"image"}, .outputs = {"image"}},
//       {bind(&SplashSettings::enabled, enabledParam()),
//        bind(&SplashSettings::opacity, fractionParam("opacity", 1.0, "..."))});
//   SplashSettings s = table.read(preset);
//
// A row's member type says how its value is read: double (Number), a whole-number type (Integer,
// or a Number truncated toward zero), bool, std::string (String, Enum), std::array<float, 3>
// (Color3), nlohmann::json (the value as given: lists), or Ramp, which also marks the row
// keyframable (a Ramp is what a frame-by-frame reader takes). An enum member is bound through
// a table of its names (bind(&S::model, "model", {{"exponential", FogModel::Exponential}, ...},
// help)), its default the name of the struct's. Rows without a member (`unbound`) are read by
// the section's own code: lists parsed into structs, derived fields.
#include <array>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "preset/param_table.h"
#include "preset/preset.h"
#include "preset/ramp.h"

namespace pluvia {

template <class Settings>
struct SettingsRow {
  ParamSpec spec;
  // Stores the value of `dottedKey` ("rain.wind.eddies") into the settings; empty: unbound.
  std::function<void(const Preset&, const std::string& dottedKey, Settings&)> read;
  // Whether the value of `dottedKey` equals the member's default in a default-constructed
  // Settings: a default written in both the row and the struct must be one value.
  std::function<bool(const Preset&, const std::string& dottedKey)> agreesWithStruct;
};

namespace settings_table_detail {

// The ParamTypes a member of type T can be read from.
template <class T>
bool readsFrom(ParamType type) {
  if constexpr (std::is_same_v<T, bool>) {
    return type == ParamType::Boolean;
  } else if constexpr (std::is_arithmetic_v<T> || std::is_same_v<T, Ramp>) {
    return type == ParamType::Number || type == ParamType::Integer;
  } else if constexpr (std::is_same_v<T, std::string>) {
    return type == ParamType::String || type == ParamType::Enum;
  } else if constexpr (std::is_same_v<T, std::array<float, 3>>) {
    return type == ParamType::Color3;
  } else {
    static_assert(std::is_same_v<T, nlohmann::json>, "no preset reader for this member type");
    return true;
  }
}

template <class T>
T readValue(const Preset& preset, const std::string& dottedKey) {
  if constexpr (std::is_same_v<T, bool>) {
    return preset.boolean(dottedKey);
  } else if constexpr (std::is_same_v<T, Ramp>) {
    return preset.ramp(dottedKey);
  } else if constexpr (std::is_arithmetic_v<T>) {
    return static_cast<T>(preset.number(dottedKey));
  } else if constexpr (std::is_same_v<T, std::string>) {
    return preset.string(dottedKey);
  } else if constexpr (std::is_same_v<T, std::array<float, 3>>) {
    return preset.color(dottedKey);
  } else {
    return preset.at(dottedKey);
  }
}

// Checks that the member can hold the row (a programming error in a section's table otherwise)
// and marks a Ramp's row keyframable.
template <class T>
ParamSpec checked(ParamSpec spec) {
  if (!readsFrom<T>(spec.type))
    throw std::logic_error("settings table: '" + spec.key + "' (" + paramTypeName(spec.type) +
                           ") is bound to a member of another type");
  if constexpr (std::is_same_v<T, Ramp>) spec.keyframes = true;
  return spec;
}

// Whether `value` equals `structDefault` (a Ramp: a constant of that value).
template <class T>
bool sameDefault(const T& value, const T& structDefault) {
  if constexpr (std::is_same_v<T, Ramp>) {
    return !value.animated() && !structDefault.animated() &&
           value.firstValue() == structDefault.firstValue();
  } else {
    return value == structDefault;
  }
}

}  // namespace settings_table_detail

// The row `spec` read into `settings.*member`.
template <class Settings, class T>
SettingsRow<Settings> bind(T Settings::*member, ParamSpec spec) {
  return {settings_table_detail::checked<T>(std::move(spec)),
          [member](const Preset& preset, const std::string& dottedKey, Settings& settings) {
            settings.*member = settings_table_detail::readValue<T>(preset, dottedKey);
          },
          [member](const Preset& preset, const std::string& dottedKey) {
            return settings_table_detail::sameDefault(
                settings_table_detail::readValue<T>(preset, dottedKey), Settings{}.*member);
          }};
}

// The row `spec` read into a member of a nested struct: `settings.*group.*member`
// (bind(&RainSettings::wind, &RainSettings::Wind::eddies, numberParam("wind.eddies", ...))).
template <class Settings, class Group, class T>
SettingsRow<Settings> bind(Group Settings::*group, T Group::*member, ParamSpec spec) {
  return {settings_table_detail::checked<T>(std::move(spec)),
          [group, member](const Preset& preset, const std::string& dottedKey, Settings& settings) {
            settings.*group.*member = settings_table_detail::readValue<T>(preset, dottedKey);
          },
          [group, member](const Preset& preset, const std::string& dottedKey) {
            return settings_table_detail::sameDefault(
                settings_table_detail::readValue<T>(preset, dottedKey), Settings{}.*group.*member);
          }};
}

// An enum row's preset names and the C++ values they stand for: one table gives the row its
// choices and its default (the name of the struct's default value) and reads the value.
template <class E>
struct EnumName {
  std::string name;
  E value;
};

// The enum row `key` read into `settings.*member` through `names`.
template <class Settings, class E>
SettingsRow<Settings> bind(E Settings::*member, std::string key, std::vector<EnumName<E>> names,
                           std::string help) {
  static_assert(std::is_enum_v<E>, "an enum row binds an enum member");
  std::vector<std::string> choices;
  std::string defaultName;
  for (const EnumName<E>& n : names) {
    choices.push_back(n.name);
    if (n.value == Settings{}.*member) defaultName = n.name;
  }
  if (defaultName.empty())
    throw std::logic_error("settings table: the default of '" + key + "' has no name");
  auto read = [member, names](const Preset& preset, const std::string& dottedKey,
                              Settings& settings) {
    const std::string name = preset.string(dottedKey);
    for (const EnumName<E>& n : names)
      if (n.name == name) {
        settings.*member = n.value;
        return;
      }
    // validatePreset refused any other name before a table reads the preset.
    throw std::logic_error("settings table: '" + dottedKey + "' is not one of its names");
  };
  return {enumParam(std::move(key), defaultName, std::move(choices), std::move(help)),
          std::move(read),
          {}};
}

// A row the section's own code reads (see the top of this file).
template <class Settings>
SettingsRow<Settings> unbound(ParamSpec spec) {
  return {std::move(spec), {}, {}};
}

template <class Settings>
class SettingsTable {
 public:
  // `section`: name, help, inputs, outputs and `increasing`; its params are the rows'.
  SettingsTable(SectionSpec section, std::vector<SettingsRow<Settings>> rows)
      : section_(std::move(section)), rows_(std::move(rows)) {
    section_.params.clear();
    for (const auto& row : rows_) section_.params.push_back(row.spec);
  }

  const SectionSpec& section() const { return section_; }

  // The bound members from the resolved preset; the others keep their defaults. A struct with a
  // `resolved` member also gets the section as the preset resolved it: the cache keys of what
  // depends on the section hash it (the JSON text, so a key does not change with how a number
  // was written).
  Settings read(const Preset& preset) const {
    Settings settings;
    for (const auto& row : rows_)
      if (row.read) row.read(preset, section_.name + "." + row.spec.key, settings);
    if constexpr (requires { settings.resolved; }) settings.resolved = preset.at(section_.name);
    return settings;
  }

  // The keys of the bound rows whose value in `defaults` (a preset that sets none of them, so
  // each row's own default) is not the struct's default: one default written twice, two values.
  std::vector<std::string> keysWhoseStructDefaultDiffers(const Preset& defaults) const {
    std::vector<std::string> keys;
    for (const auto& row : rows_) {
      if (!row.agreesWithStruct || row.spec.defaultValue.is_null()) continue;
      if (!row.agreesWithStruct(defaults, section_.name + "." + row.spec.key))
        keys.push_back(section_.name + "." + row.spec.key);
    }
    return keys;
  }

 private:
  SectionSpec section_;
  std::vector<SettingsRow<Settings>> rows_;
};

}  // namespace pluvia
