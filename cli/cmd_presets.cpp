// `pluvia presets`: the presets a render can name, each with what it sets the rain to look like,
// so that a compositor can choose one without opening the JSON files.
#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "common.h"
#include "preset/preset.h"

namespace pluvia::cli {
namespace {

// A shipped preset's look, read from its resolved JSON (defaults filled in).
struct PresetLook {
  std::string name, description;
  double rateMmPerHour, windMPerS, fogDensityPerM, darken, exposureS;
  std::string file;
};

PresetLook lookOf(const std::string& name) {
  const Preset preset = loadPreset(name, {});
  PresetLook look;
  look.name = name;
  look.file = findPreset(name).string();
  const nlohmann::json& json = preset.json();
  look.description = json.value("description", "");
  look.rateMmPerHour = preset.number("rain.rate_mm_h");
  look.windMPerS = preset.number("rain.wind.speed_m_s");
  look.fogDensityPerM = preset.number("fog.density");
  look.darken = preset.number("darken.amount");
  look.exposureS = preset.number("camera.exposure_s");
  return look;
}

// Exposure 0 means the plate camera's own shutter (camera.exposure_s).
std::string shutterText(double exposureS) {
  return exposureS > 0 ? fmt::format("1/{:g} s", 1.0 / exposureS) : "plate's";
}

// `text` broken into lines of at most `width` characters, each after `indent`.
std::string wrapped(const std::string& text, size_t width, const std::string& indent) {
  std::string out, line;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      out += indent + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    start = end + 1;
  }
  if (!line.empty()) out += indent + line + "\n";
  return out;
}

}  // namespace

void addPresetsCommand(CLI::App& app, Invocation&) {
  auto* cmd =
      app.add_subcommand("presets",
                         "list the presets -p can name: rain rate, wind, fog, darkening, shutter, "
                         "description");
  auto asJson = std::make_shared<bool>(false);
  cmd->add_flag("--json", *asJson, "one JSON array instead of the table (for scripts)");
  cmd->callback([=] {
    std::vector<PresetLook> looks;
    bool hasBase = false;
    for (const std::string& name : shippedPresetNames()) {
      if (name == "base")
        hasBase = true;
      else
        looks.push_back(lookOf(name));
    }
    // Lightest rain first: the list reads as a scale.
    std::stable_sort(looks.begin(), looks.end(), [](const PresetLook& a, const PresetLook& b) {
      return a.rateMmPerHour < b.rateMmPerHour;
    });
    // A sheet across the scale: the lightest, the middle and the heaviest.
    std::vector<std::string> example;
    for (size_t i : {size_t(0), looks.size() / 2, looks.size() - 1})
      if (i < looks.size() && (example.empty() || example.back() != looks[i].name))
        example.push_back(looks[i].name);
    // base is what the others extend: last, as the start of a preset of one's own.
    if (hasBase) looks.push_back(lookOf("base"));
    if (*asJson) {
      nlohmann::json list = nlohmann::json::array();
      for (const PresetLook& look : looks)
        list.push_back({{"name", look.name},
                        {"file", look.file},
                        {"description", look.description},
                        {"rate_mm_h", look.rateMmPerHour},
                        {"wind_speed_m_s", look.windMPerS},
                        {"fog_density_per_m", look.fogDensityPerM},
                        {"darken_amount", look.darken},
                        {"exposure_s", look.exposureS}});
      std::cout << list.dump(2) << "\n";
      return;
    }
    std::cout << fmt::format("{:<10} {:>9} {:>8} {:>8} {:>7} {:>9}\n", "PRESET", "RAIN mm/h",
                             "WIND m/s", "FOG 1/m", "DARKEN", "SHUTTER");
    for (const PresetLook& look : looks) {
      std::cout << fmt::format("{:<10} {:>9g} {:>8g} {:>8g} {:>7g} {:>9}\n", look.name,
                               look.rateMmPerHour, look.windMPerS, look.fogDensityPerM, look.darken,
                               shutterText(look.exposureS));
      std::cout << wrapped(look.description, 88, "    ");
    }
    std::cout << "\nSHUTTER plate's: the plate camera's own (camera.exposure_s 0). Compare "
                 "them on your plate:\n  pluvia preview CLIP --presets "
              << fmt::format("{}", fmt::join(example, ",")) << " -o sheet.png\n";
  });
}

}  // namespace pluvia::cli
