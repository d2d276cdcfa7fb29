#include "image/transfer_lut.h"

#include <bit>

namespace pluvia {
namespace {

constexpr uint32_t kMantissaBits = 23;
constexpr uint32_t kNodeShift = kMantissaBits - 10;  // 1024 nodes per octave
static_assert(TransferLut::kNodesPerOctave == 1 << (kMantissaBits - kNodeShift));
constexpr uint32_t kFirstBits = static_cast<uint32_t>(127 + TransferLut::kLowestExponent)
                                << kMantissaBits;
constexpr uint32_t kEndBits =
    static_cast<uint32_t>(127 + TransferLut::kLowestExponent + TransferLut::kOctaves)
    << kMantissaBits;
constexpr size_t kNodes = static_cast<size_t>(TransferLut::kOctaves) * TransferLut::kNodesPerOctave;
constexpr float kStepFraction = 1.0f / static_cast<float>(1u << kNodeShift);

// The table value of x, or false when x is outside the table. x = 0 is exact.
inline bool lookUp(const float* table, float atZero, float x, float& out) {
  const uint32_t bits = std::bit_cast<uint32_t>(x);
  if (bits - kFirstBits < kEndBits - kFirstBits) {
    const uint32_t node = (bits - kFirstBits) >> kNodeShift;
    const float t = static_cast<float>(bits & ((1u << kNodeShift) - 1)) * kStepFraction;
    const float* entry = table + 2 * static_cast<size_t>(node);
    out = entry[0] + t * entry[1];
    return true;
  }
  out = atZero;
  return bits == 0;
}

}  // namespace

TransferLut::TransferLut(const ExactRgb& exact) : exact_(exact) {
  // Every node and the end of the last octave, in each of R, G, B, and zero.
  std::vector<float> rgb((kNodes + 2) * 3);
  for (size_t j = 0; j <= kNodes; ++j) {
    const float x = std::bit_cast<float>(kFirstBits + (static_cast<uint32_t>(j) << kNodeShift));
    for (int c = 0; c < 3; ++c) rgb[j * 3 + c] = x;
  }
  for (int c = 0; c < 3; ++c) rgb[(kNodes + 1) * 3 + c] = 0.0f;
  exact_(rgb.data(), kNodes + 2);
  for (int c = 0; c < 3; ++c) {
    table_[c].resize(2 * kNodes);
    for (size_t j = 0; j < kNodes; ++j) {
      table_[c][2 * j] = rgb[j * 3 + c];
      table_[c][2 * j + 1] = rgb[(j + 1) * 3 + c] - rgb[j * 3 + c];
    }
    atZero_[c] = rgb[(kNodes + 1) * 3 + c];
  }
}

size_t TransferLut::apply(float* rgba, size_t count) const {
  std::vector<size_t> misses;
  for (size_t i = 0; i < count; ++i) {
    float* p = rgba + i * 4;
    float out[3];
    bool inTable = true;
    for (int c = 0; c < 3; ++c) inTable &= lookUp(table_[c].data(), atZero_[c], p[c], out[c]);
    if (inTable) {
      p[0] = out[0], p[1] = out[1], p[2] = out[2];
    } else {
      misses.push_back(i);
    }
  }
  if (misses.empty()) return 0;
  std::vector<float> rgb(misses.size() * 3);
  for (size_t k = 0; k < misses.size(); ++k) {
    for (int c = 0; c < 3; ++c) rgb[k * 3 + c] = rgba[misses[k] * 4 + c];
  }
  exact_(rgb.data(), misses.size());
  for (size_t k = 0; k < misses.size(); ++k) {
    for (int c = 0; c < 3; ++c) rgba[misses[k] * 4 + c] = rgb[k * 3 + c];
  }
  return misses.size();
}

}  // namespace pluvia
