#include "foveation/foveation_mask.h"

#include <algorithm>

namespace fovlab {

namespace {
// Chris Wellons' lowbias32 (hash-prospector, 2020): a 32-bit bijective mixer with low bias.
uint32_t lowbias32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}
}  // namespace

const char* mask_combine_name(MaskCombine combine) {
  switch (combine) {
    case MaskCombine::max:
      return "max";
    case MaskCombine::fovea_or_product:
      return "fovea-or-product";
    case MaskCombine::product:
      return "product";
    case MaskCombine::acuity:
      return "acuity";
  }
  return "max";
}

std::optional<MaskCombine> parse_mask_combine(const std::string& name) {
  for (MaskCombine combine :
       {MaskCombine::max, MaskCombine::fovea_or_product, MaskCombine::product, MaskCombine::acuity})
    if (name == mask_combine_name(combine)) return combine;
  return std::nullopt;
}

double mask_probability(MaskCombine combine, double acuity_probability, bool in_fovea, bool edge) {
  const double edge_value = edge ? 1.0 : 0.0;
  switch (combine) {
    case MaskCombine::max:
      return std::max(acuity_probability, edge_value);
    case MaskCombine::fovea_or_product:
      return in_fovea ? 1.0 : acuity_probability * edge_value;
    case MaskCombine::product:
      return acuity_probability * edge_value;
    case MaskCombine::acuity:
      return acuity_probability;
  }
  return acuity_probability;
}

uint32_t mask_hash(uint32_t seed, uint32_t frame, uint32_t x, uint32_t y) {
  return lowbias32(x + lowbias32(y + lowbias32(frame + lowbias32(seed))));
}

double mask_threshold(uint32_t seed, uint32_t frame, uint32_t x, uint32_t y) {
  return double(mask_hash(seed, frame, x, y) >> 8) * (1.0 / 16777216.0);
}

}  // namespace fovlab
