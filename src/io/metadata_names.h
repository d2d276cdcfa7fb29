#pragma once
// Makers name the same field many ways ("shutter_angle", "com.arri.camera.ShutterAngle",
// ffprobe's flat "com_sony_shutter_speed"): compared folded, lower case without '_', '-' or
// spaces, by how the name ends.
#include <algorithm>
#include <cctype>
#include <string>
#include <string_view>

namespace pluvia {

// Whether `name`, folded, ends with `foldedSuffix` (given folded: "shutterangle").
inline bool metadataNameEndsWith(std::string name, std::string_view foldedSuffix) {
  std::erase_if(name, [](char c) { return c == '_' || c == '-' || c == ' '; });
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return name.ends_with(foldedSuffix);
}

}  // namespace pluvia
