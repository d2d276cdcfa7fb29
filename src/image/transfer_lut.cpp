#include "image/transfer_lut.h"

#include <algorithm>
#include <bit>

#include <immintrin.h>

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

// Pixels [begin, end) the scalar way; a pixel with a value outside the table joins `misses`.
void applyScalar(const float* tables, const float* atZero, float* rgba, size_t begin, size_t end,
                 std::vector<size_t>& misses) {
  for (size_t i = begin; i < end; ++i) {
    float* p = rgba + i * 4;
    float out[3];
    bool inTable = true;
    for (int c = 0; c < 3; ++c) inTable &= lookUp(tables + c * 2 * kNodes, atZero[c], p[c], out[c]);
    if (inTable) {
      p[0] = out[0], p[1] = out[1], p[2] = out[2];
    } else {
      misses.push_back(i);
    }
  }
}

// The same lookup two pixels at a time with AVX2 gathers: the same float operations in the
// same order (a product, then a sum: no fused multiply-add), so the same values bit for bit.
// Returns the first pixel it left to the scalar loop.
__attribute__((target("avx2"))) size_t applyAvx2(const float* tables, const float* atZero,
                                                 float* rgba, size_t count,
                                                 std::vector<size_t>& misses) {
  const __m256i first = _mm256_set1_epi32(int(kFirstBits));
  const __m256i signBit = _mm256_set1_epi32(int(0x80000000u));
  const __m256i spanSigned =
      _mm256_xor_si256(_mm256_set1_epi32(int(kEndBits - kFirstBits)), signBit);
  const __m256i fractionMask = _mm256_set1_epi32(int((1u << kNodeShift) - 1));
  const __m256 stepFraction = _mm256_set1_ps(kStepFraction);
  // Lanes are R, G, B, A of two pixels; each colour lane reads its channel's table.
  const int channel = int(2 * kNodes);
  const __m256i tableOffsets =
      _mm256_setr_epi32(0, channel, 2 * channel, 0, 0, channel, 2 * channel, 0);
  const __m256 zeroValues =
      _mm256_setr_ps(atZero[0], atZero[1], atZero[2], 0.0f, atZero[0], atZero[1], atZero[2], 0.0f);
  constexpr int kAlphaLanes = 0b10001000;
  size_t i = 0;
  for (; i + 2 <= count; i += 2) {
    float* p = rgba + i * 4;
    const __m256 x = _mm256_loadu_ps(p);
    const __m256i bits = _mm256_castps_si256(x);
    const __m256i fromFirst = _mm256_sub_epi32(bits, first);
    // Unsigned fromFirst < span, as a signed comparison with the sign bits flipped.
    const __m256i inTable = _mm256_cmpgt_epi32(spanSigned, _mm256_xor_si256(fromFirst, signBit));
    const __m256i isZero = _mm256_cmpeq_epi32(bits, _mm256_setzero_si256());
    const int hit = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_or_si256(inTable, isZero)));
    const __m256i node = _mm256_and_si256(_mm256_srli_epi32(fromFirst, int(kNodeShift)), inTable);
    const __m256i index = _mm256_add_epi32(_mm256_slli_epi32(node, 1), tableOffsets);
    const __m256 value = _mm256_i32gather_ps(tables, index, 4);
    const __m256 slope = _mm256_i32gather_ps(tables + 1, index, 4);
    const __m256 t =
        _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(bits, fractionMask)), stepFraction);
    __m256 out = _mm256_add_ps(value, _mm256_mul_ps(t, slope));
    out = _mm256_blendv_ps(zeroValues, out, _mm256_castsi256_ps(inTable));
    out = _mm256_blend_ps(out, x, kAlphaLanes);
    const bool firstHit = (hit & 0b0111) == 0b0111, secondHit = (hit & 0b01110000) == 0b01110000;
    if (firstHit && secondHit) {
      _mm256_storeu_ps(p, out);
      continue;
    }
    alignas(32) float lanes[8];
    _mm256_store_ps(lanes, out);
    if (firstHit)
      std::copy(lanes, lanes + 3, p);
    else
      misses.push_back(i);
    if (secondHit)
      std::copy(lanes + 4, lanes + 7, p + 4);
    else
      misses.push_back(i + 1);
  }
  return i;
}

bool cpuHasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
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
  tables_.resize(3 * 2 * kNodes);
  for (int c = 0; c < 3; ++c) {
    float* table = tables_.data() + c * 2 * kNodes;
    for (size_t j = 0; j < kNodes; ++j) {
      table[2 * j] = rgb[j * 3 + c];
      table[2 * j + 1] = rgb[(j + 1) * 3 + c] - rgb[j * 3 + c];
    }
    atZero_[c] = rgb[(kNodes + 1) * 3 + c];
  }
}

size_t TransferLut::apply(float* rgba, size_t count) const {
  std::vector<size_t> misses;
  const size_t scalarFrom =
      cpuHasAvx2() ? applyAvx2(tables_.data(), atZero_, rgba, count, misses) : 0;
  applyScalar(tables_.data(), atZero_, rgba, scalarFrom, count, misses);
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
