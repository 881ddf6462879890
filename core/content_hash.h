#pragma once
// FNV-1a, 64 bits: a stable content hash for cache keys (shader cache, pre-rendered buffers).
// Not cryptographic; the same bytes give the same hash on every platform and standard library.
#include <cstdint>
#include <string>
#include <string_view>

namespace fovlab {

class ContentHash {
 public:
  // Adds the bytes and then their length, so ("ab","c") and ("a","bc") hash differently.
  ContentHash& add(std::string_view bytes) {
    for (unsigned char byte : bytes) mix(byte);
    const uint64_t length = bytes.size();
    for (int shift = 0; shift < 64; shift += 8) mix(static_cast<unsigned char>(length >> shift));
    return *this;
  }
  uint64_t value() const { return state_; }
  std::string hex() const {
    static constexpr char digits[] = "0123456789abcdef";
    std::string text(16, '0');
    for (int i = 0; i < 16; ++i) text[static_cast<size_t>(15 - i)] = digits[(state_ >> (4 * i)) & 0xF];
    return text;
  }

 private:
  void mix(unsigned char byte) {
    state_ ^= byte;
    state_ *= 0x100000001b3ULL;  // FNV 64-bit prime
  }
  uint64_t state_ = 0xcbf29ce484222325ULL;  // FNV 64-bit offset basis
};

}  // namespace fovlab
