#pragma once
// The three kinds of rain of Mizukami et al. (Table 1): rainfall, a typical drop diameter and
// the fall speed they give to every drop of that kind.
#include <string>
#include <vector>

namespace pluvia::rain {

struct RainType {
  std::string name;
  double rateMmH;
  double meanDiameterMm;
  double speedMetersPerSecond;
};

// nullptr for an unknown name.
const RainType* findRainType(const std::string& name);

// "gentle", "hard", "heavy": lightest first.
std::vector<std::string> rainTypeNames();

}  // namespace pluvia::rain
