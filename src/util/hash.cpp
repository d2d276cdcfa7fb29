#include "util/hash.h"

#include <fmt/format.h>
#include <cstring>

namespace pluvia {

Hasher& Hasher::add(std::string_view bytes) {
  for (unsigned char c : bytes) {
    state_ ^= c;
    state_ *= 0x100000001b3ull;
  }
  // Length terminator so that add("ab") + add("c") differs from add("a") + add("bc").
  return add(static_cast<uint64_t>(bytes.size()));
}

Hasher& Hasher::add(uint64_t value) {
  for (int i = 0; i < 8; ++i) {
    state_ ^= (value >> (8 * i)) & 0xffu;
    state_ *= 0x100000001b3ull;
  }
  return *this;
}

Hasher& Hasher::add(double value) {
  uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return add(bits);
}

std::string Hasher::hex() const {
  return fmt::format("{:016x}", state_);
}

uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

uint64_t CounterRng::nextU64() {
  state_ += 0x9e3779b97f4a7c15ull;
  return mix64(state_);
}

double CounterRng::uniform() {
  return static_cast<double>(nextU64() >> 11) * 0x1.0p-53;
}

}  // namespace pluvia
