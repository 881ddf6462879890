#pragma once
// The one PRNG of everything that must replay (schedules, simulated observers, synthetic gaze):
// PCG32 (O'Neill 2014, "PCG-XSH-RR 64/32") seeded through SplitMix64 (Steele et al. 2014).
// Integers in a range use rejection (no modulo bias), floats take the top 24 or 53 bits, and
// shuffles are our own Fisher-Yates, so a seed gives the same sequence with every compiler and
// standard library (std::uniform_*_distribution and std::shuffle do not promise that).
#include <cmath>
#include <cstdint>
#include <string_view>
#include <utility>
#include <vector>

namespace fovlab {

// SplitMix64 finaliser: a good 64-bit mixing function, also used to derive independent seeds.
inline uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// A seed for a named sub-stream ("schedule", "observer", trial 17...): the same (seed, parts) give
// the same stream, different parts give unrelated streams.
inline uint64_t derive_seed(uint64_t seed, uint64_t part) {
  uint64_t state = seed ^ (part * 0xd1b54a32d192ed03ULL);
  splitmix64(state);
  return splitmix64(state);
}
inline uint64_t derive_seed(uint64_t seed, std::string_view name) {
  uint64_t hash = 0xcbf29ce484222325ULL;  // FNV-1a of the name
  for (unsigned char c : name) hash = (hash ^ c) * 0x100000001b3ULL;
  return derive_seed(seed, hash);
}

class Pcg32 {
 public:
  explicit Pcg32(uint64_t seed) {
    uint64_t mixer = seed;
    state_ = splitmix64(mixer);
    increment_ = splitmix64(mixer) | 1u;
    next_u32();
  }

  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + increment_;
    const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rotation = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rotation) | (xorshifted << ((32u - rotation) & 31u));
  }

  // Uniform integer in [0, bound), bound >= 1, by rejection of the biased low range.
  uint32_t below(uint32_t bound) {
    const uint32_t threshold = (0u - bound) % bound;
    for (;;) {
      const uint32_t r = next_u32();
      if (r >= threshold) return r % bound;
    }
  }

  // Uniform double in [0, 1) with 53 random bits.
  double uniform() {
    const uint64_t high = next_u32() >> 5;  // 27 bits
    const uint64_t low = next_u32() >> 6;   // 26 bits
    return static_cast<double>((high << 26) | low) * 0x1.0p-53;
  }
  double uniform(double low, double high) { return low + (high - low) * uniform(); }

  // Standard normal by Box-Muller (no cached second value, so the stream stays simple to replay).
  double normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
  // Exponential with the given mean.
  double exponential(double mean) { return -mean * std::log(1.0 - uniform()); }

  template <typename T>
  void shuffle(std::vector<T>& items) {  // Fisher-Yates, last to first
    for (size_t i = items.size(); i > 1; --i) {
      const size_t j = below(static_cast<uint32_t>(i));
      std::swap(items[i - 1], items[j]);
    }
  }

 private:
  uint64_t state_ = 0;
  uint64_t increment_ = 1;
};

}  // namespace fovlab
