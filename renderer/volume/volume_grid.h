#pragma once
// The scalar volumes the volume raycaster draws (Bruder et al. 2019): a grid of voxels, each a 16-bit value
// on the transfer function's axis (0 to 65535 for 0 to 1), with its voxel spacing. Three are
// generated at any size, deterministically:
//   - marschner-lobb: the Marschner-Lobb test signal (Marschner and Lobb 1994, alpha 0.25, f_M 6)
//     on [-1, 1]^3, the classic test of a reconstruction filter;
//   - combustion: a turbulent, flame-like field (absolute-value noise summed over octaves, inside a
//     rising plume), seeded with core/prng.h;
//   - shepp-logan: a 3-D Shepp-Logan-style CT phantom (ten ellipsoids, the modified intensities).
// Files a lab already has are read too: NRRD (through Debian's libteem) and the raw .dat format of
// the volume-visualisation data sets (three little-endian uint16 sides, then uint16 voxels, x
// fastest). Sizes are checked against the limits before a voxel is allocated or read.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fovlab {

struct VolumeGrid {
  std::array<int, 3> size_voxels{0, 0, 0};       // x, y, z
  std::array<double, 3> spacing{1.0, 1.0, 1.0};  // voxel size along x, y, z (any unit; ratios matter)
  std::vector<uint16_t> values;                  // x fastest, then y, then z

  uint64_t voxel_count() const {
    return uint64_t(size_voxels[0]) * uint64_t(size_voxels[1]) * uint64_t(size_voxels[2]);
  }
  uint16_t at(int x, int y, int z) const {
    return values[size_t((uint64_t(z) * uint64_t(size_voxels[1]) + uint64_t(y)) * uint64_t(size_voxels[0]) +
                         uint64_t(x))];
  }
};

// What a volume may be on the device that draws it: voxels a side (the device's 3-D image limit) and
// bytes in all (its largest storage buffer, and the memory available).
struct VolumeLimits {
  int max_side_voxels = 2048;
  uint64_t max_bytes = uint64_t(1) << 31;
};

// Throws InputError "<what>: <X>x<Y>x<Z> voxels: expected ..." when a side is under 1 or over the
// limit, or the voxels (2 bytes each) exceed max_bytes.
void check_volume_size(const std::array<int64_t, 3>& size_voxels, const VolumeLimits& limits, const std::string& what);

enum class GeneratedVolume { marschner_lobb, combustion, shepp_logan };
std::optional<GeneratedVolume> find_generated_volume(std::string_view name);
std::string_view generated_volume_name(GeneratedVolume kind);
std::string generated_volume_names();  // "marschner-lobb, combustion, shepp-logan"

// The generated volume at size_voxels a side (cubic voxels). The value at a voxel is the field at the
// voxel's centre. `seed` drives combustion only.
VolumeGrid generate_volume(GeneratedVolume kind, int size_voxels, uint64_t seed, const VolumeLimits& limits);
// The continuous fields, in [0, 1], at a point of [-1, 1]^3 (the CPU reference the tests use).
double marschner_lobb(double x, double y, double z);
double shepp_logan(double x, double y, double z);

// How a file's values map to the transfer function's 0..1: the given range; without one, an integer
// type's whole range (0..255, 0..65535; a .dat's 0..4095 when every value fits 12 bits), and a
// floating-point file's smallest to largest finite value. Values outside clamp; NaN reads as the
// low end, +inf as the high end, -inf as the low end.
struct ValueRange {
  double low = 0.0, high = 1.0;
};

// Reads a .nrrd/.nhdr or .dat volume. InputError naming the file and what was wrong: not a 3-D scalar
// volume, a type fovlab does not read, sides out of the limits (from the header, before the voxels
// are read), a file shorter than its header says, a range that is not low < high.
VolumeGrid load_volume_file(const std::filesystem::path& path, const std::optional<ValueRange>& range,
                            const VolumeLimits& limits);

}  // namespace fovlab
