#include "rain/rain_types.h"

#include <array>

namespace pluvia::rain {

namespace {

const std::array<RainType, 3>& rainTypes() {
  static const std::array<RainType, 3> types = {{
      {"gentle", 4.0, 1.0, 4.0},
      {"hard", 15.0, 1.5, 5.0},
      {"heavy", 40.0, 2.0, 6.0},
  }};
  return types;
}

}  // namespace

const RainType* findRainType(const std::string& name) {
  for (const RainType& type : rainTypes())
    if (type.name == name) return &type;
  return nullptr;
}

std::vector<std::string> rainTypeNames() {
  std::vector<std::string> names;
  for (const RainType& type : rainTypes()) names.push_back(type.name);
  return names;
}

}  // namespace pluvia::rain
