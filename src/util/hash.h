#pragma once
// 64-bit FNV-1a hashing for cache keys and preset hashes, and a counter-based random
// generator (SplitMix64) so that every drop's randomness depends only on (seed, index),
// never on thread count or render order.
#include <cstdint>
#include <string>
#include <string_view>

namespace pluvia {

class Hasher {
 public:
  Hasher& add(std::string_view bytes);
  Hasher& add(uint64_t value);
  Hasher& add(double value);
  uint64_t value() const { return state_; }
  std::string hex() const;  // 16 hex digits

 private:
  uint64_t state_ = 0xcbf29ce484222325ull;
};

// SplitMix64 finaliser: a good 64-bit mix of one value.
uint64_t mix64(uint64_t x);

// Deterministic stream of uniform numbers for one (seed, stream) pair.
class CounterRng {
 public:
  CounterRng(uint64_t seed, uint64_t stream)
      : state_(mix64(seed ^ mix64(stream + 0x9e3779b97f4a7c15ull))) {}
  uint64_t nextU64();
  double uniform();  // [0, 1)
 private:
  uint64_t state_;
};

}  // namespace pluvia
