#include "preset/ramp.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "util/error.h"

namespace pluvia {

namespace {

// Each interpolation with its name in a preset: the one list that naming, parsing and the
// validator's messages read.
constexpr std::array<std::pair<RampInterpolation, const char*>, 3> kInterpolationNames{{
    {RampInterpolation::Linear, "linear"},
    {RampInterpolation::Smooth, "smooth"},
    {RampInterpolation::Hold, "hold"},
}};

}  // namespace

const char* rampInterpolationName(RampInterpolation interpolation) {
  for (const auto& [value, name] : kInterpolationNames)
    if (value == interpolation) return name;
  return "linear";
}

bool parseRampInterpolation(const std::string& name, RampInterpolation& interpolation) {
  for (const auto& [value, candidate] : kInterpolationNames) {
    if (name == candidate) {
      interpolation = value;
      return true;
    }
  }
  return false;
}

std::vector<std::string> rampInterpolationNames() {
  std::vector<std::string> names;
  for (const auto& [value, name] : kInterpolationNames) names.emplace_back(name);
  return names;
}

Ramp::Ramp(double constant) : keys_{RampKey{0.0, constant}} {}

Ramp::Ramp(std::vector<RampKey> keys, RampInterpolation interpolation)
    : keys_(std::move(keys)), interpolation_(interpolation) {
  if (keys_.empty()) throw Error("a ramp needs at least one key");
  for (size_t i = 0; i < keys_.size(); ++i) {
    if (!std::isfinite(keys_[i].frame) || !std::isfinite(keys_[i].value))
      throw Error(fmt::format("ramp key {} is not finite", i));
    if (i > 0 && !(keys_[i].frame > keys_[i - 1].frame))
      throw Error(fmt::format("ramp key {} (frame {}) does not come after frame {}", i,
                              keys_[i].frame, keys_[i - 1].frame));
  }
}

double Ramp::maxValue() const {
  double largest = keys_.front().value;
  for (const RampKey& key : keys_) largest = std::max(largest, key.value);
  return largest;
}

bool Ramp::looksLikeKeys(const nlohmann::json& value) {
  if (value.is_object()) return value.contains("keys");
  if (!value.is_array() || value.empty()) return false;
  return std::all_of(value.begin(), value.end(), [](const nlohmann::json& pair) {
    return pair.is_array() && pair.size() == 2 && pair[0].is_number() && pair[1].is_number();
  });
}

Ramp Ramp::fromJson(const nlohmann::json& value) {
  if (value.is_number()) return Ramp(value.get<double>());
  const nlohmann::json* keys = &value;
  RampInterpolation interpolation = RampInterpolation::Linear;
  if (value.is_object()) {
    if (!value.contains("keys")) throw Error("a keyframed value needs \"keys\"");
    keys = &value["keys"];
    if (value.contains("interpolation")) {
      if (!value["interpolation"].is_string() ||
          !parseRampInterpolation(value["interpolation"].get<std::string>(), interpolation))
        throw Error("\"interpolation\" must be linear, smooth or hold, not " +
                    value["interpolation"].dump());
    }
  }
  if (!keys->is_array()) throw Error("expected a number or keys, got " + value.dump());
  std::vector<RampKey> parsed;
  for (const auto& pair : *keys) {
    if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number() || !pair[1].is_number())
      throw Error("a key must be [frame, value], got " + pair.dump());
    parsed.push_back({pair[0].get<double>(), pair[1].get<double>()});
  }
  return Ramp(std::move(parsed), interpolation);
}

double Ramp::valueAt(double frame) const {
  if (std::isnan(frame) || frame <= keys_.front().frame) return keys_.front().value;
  if (frame >= keys_.back().frame) return keys_.back().value;
  // The first key after `frame`; the one before it is at or before `frame`.
  auto next = std::upper_bound(keys_.begin(), keys_.end(), frame,
                               [](double f, const RampKey& key) { return f < key.frame; });
  const RampKey& b = *next;
  const RampKey& a = *(next - 1);
  double t = (frame - a.frame) / (b.frame - a.frame);
  switch (interpolation_) {
    case RampInterpolation::Hold:
      return a.value;
    case RampInterpolation::Smooth:
      t = t * t * (3.0 - 2.0 * t);
      break;
    case RampInterpolation::Linear:
      break;
  }
  return a.value + (b.value - a.value) * t;
}

bool Ramp::animated() const {
  return std::any_of(keys_.begin(), keys_.end(),
                     [&](const RampKey& k) { return k.value != keys_.front().value; });
}

}  // namespace pluvia
