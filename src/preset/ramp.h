#pragma once
// Keyframed numbers ("ramps"). A Number or Integer parameter of a preset section marked keyframable
// (ParamSpec::keyframes) may be given as a plain number or as keys over clip frame numbers (the
// numbers the renderer calls `frame`):
//
//   "rate_mm_h": {"keys": [[0, 0], [48, 40]], "interpolation": "linear"}
//
// interpolation: "linear" (the default), "smooth" (smoothstep between neighbouring keys) or
// "hold" (each key's value until the next key). Before the first key the first value holds,
// after the last key the last value holds. A bare list of [frame, value] pairs is shorthand for
// {"keys": [...]} (`--set rain.rate_mm_h=[[0,0],[48,40]]`); Preset::resolve stores the object form.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pluvia {

enum class RampInterpolation { Linear, Smooth, Hold };
const char* rampInterpolationName(RampInterpolation interpolation);
// "linear" | "smooth" | "hold" -> the value; false when the name is none of them.
bool parseRampInterpolation(const std::string& name, RampInterpolation& interpolation);
// Every interpolation's name, "linear" (the default) first.
std::vector<std::string> rampInterpolationNames();

struct RampKey {
  double frame = 0.0;
  double value = 0.0;
};

class Ramp {
 public:
  Ramp() = default;  // the constant 0
  explicit Ramp(double constant);
  // Keys in strictly increasing frame order, at least one; throws pluvia::Error otherwise.
  explicit Ramp(std::vector<RampKey> keys,
                RampInterpolation interpolation = RampInterpolation::Linear);

  // A plain number, a keyframe object {"keys": [...], "interpolation": ...} or a bare list of
  // [frame, value] pairs. Throws pluvia::Error when it is none of them (validatePreset reports
  // the details with paths; this is for values that already passed validation).
  static Ramp fromJson(const nlohmann::json& value);
  // True for the keyframe object or the bare pair list (what fromJson reads besides numbers).
  static bool looksLikeKeys(const nlohmann::json& value);

  double valueAt(double frame) const;
  double firstValue() const { return keys_.front().value; }
  // The largest value the ramp takes: every interpolation stays between neighbouring keys.
  double maxValue() const;
  // True when the value changes with the frame (two or more keys with different values).
  bool animated() const;
  const std::vector<RampKey>& keys() const { return keys_; }
  RampInterpolation interpolation() const { return interpolation_; }

 private:
  std::vector<RampKey> keys_{RampKey{}};
  RampInterpolation interpolation_ = RampInterpolation::Linear;
};

}  // namespace pluvia
