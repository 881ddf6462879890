#include "renderer/volume/volume_grid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include <teem/nrrd.h>

#include "core/input_error.h"
#include "core/input_file.h"
#include "core/prng.h"

namespace fovlab {
namespace {

constexpr double kPi = 3.14159265358979323846;

uint16_t quantise(double value) {
  if (!(value > 0.0)) return 0;  // NaN too
  if (value >= 1.0) return 65535;
  return static_cast<uint16_t>(std::lround(value * 65535.0));
}

std::string size_text(const std::array<int64_t, 3>& size) {
  return std::to_string(size[0]) + "x" + std::to_string(size[1]) + "x" + std::to_string(size[2]);
}

// Value noise on the integer lattice, each lattice value a hash of (seed, i, j, k): the same on every
// machine and standard library.
double lattice_value(uint64_t seed, int64_t i, int64_t j, int64_t k) {
  uint64_t state = derive_seed(derive_seed(derive_seed(seed, uint64_t(i)), uint64_t(j)), uint64_t(k));
  return double(splitmix64(state) >> 11) * 0x1.0p-53;
}

double value_noise(uint64_t seed, double x, double y, double z) {
  const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const auto smooth = [](double t) { return t * t * (3.0 - 2.0 * t); };
  const double tx = smooth(x - fx), ty = smooth(y - fy), tz = smooth(z - fz);
  const auto i = int64_t(fx), j = int64_t(fy), k = int64_t(fz);
  double result = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
    const double weight = (dx ? tx : 1.0 - tx) * (dy ? ty : 1.0 - ty) * (dz ? tz : 1.0 - tz);
    result += weight * lattice_value(seed, i + dx, j + dy, k + dz);
  }
  return result;
}

// The combustion-like field at a point of [-1, 1]^3 (y up): turbulence (absolute-value noise over
// five octaves, Perlin's flame recipe) inside a plume that widens as it rises, brightest in a
// sheet around its core.
double combustion(uint64_t seed, double x, double y, double z) {
  double turbulence = 0.0, amplitude = 0.5, frequency = 3.0;
  for (int octave = 0; octave < 5; ++octave) {
    turbulence += amplitude * std::abs(2.0 * value_noise(seed + uint64_t(octave), x * frequency, (y - 0.3 * octave) * frequency,
                                                         z * frequency) - 1.0);
    amplitude *= 0.5;
    frequency *= 2.0;
  }
  const double height = 0.5 * (y + 1.0);  // 0 at the bottom, 1 at the top
  const double radius = std::sqrt(x * x + z * z) + 0.35 * (turbulence - 0.5);
  const double plume_radius = 0.25 + 0.45 * height;
  const double sheet = std::exp(-std::pow((radius - 0.6 * plume_radius) / (0.35 * plume_radius), 2.0));
  const double fade = std::clamp(1.2 - height, 0.0, 1.0) * std::clamp(height * 8.0, 0.0, 1.0);
  return std::clamp(sheet * fade * (0.55 + 0.9 * turbulence), 0.0, 1.0);
}

struct Ellipsoid {
  double intensity, a, b, c, x0, y0, z0, phi_deg;
};

// The 3-D Shepp-Logan phantom's ten ellipsoids with the modified (higher-contrast) intensities; the
// two tilted ones turn about the z axis only.
constexpr Ellipsoid kSheppLogan[] = {
    {1.0, 0.6900, 0.920, 0.810, 0.0, 0.0, 0.0, 0.0},       {-0.8, 0.6624, 0.874, 0.780, 0.0, -0.0184, 0.0, 0.0},
    {-0.2, 0.1100, 0.310, 0.220, 0.22, 0.0, 0.0, -18.0},   {-0.2, 0.1600, 0.410, 0.280, -0.22, 0.0, 0.0, 18.0},
    {0.1, 0.2100, 0.250, 0.410, 0.0, 0.35, -0.15, 0.0},    {0.1, 0.0460, 0.046, 0.050, 0.0, 0.1, 0.25, 0.0},
    {0.1, 0.0460, 0.046, 0.050, 0.0, -0.1, 0.25, 0.0},     {0.1, 0.0460, 0.023, 0.050, -0.08, -0.605, 0.0, 0.0},
    {0.1, 0.0230, 0.023, 0.020, 0.0, -0.606, 0.0, 0.0},    {0.1, 0.0230, 0.046, 0.020, 0.06, -0.605, 0.0, 0.0},
};

}  // namespace

double marschner_lobb(double x, double y, double z) {
  constexpr double alpha = 0.25, f_m = 6.0;
  const double r = std::sqrt(x * x + y * y);
  const double rho_r = std::cos(2.0 * kPi * f_m * std::cos(kPi * r / 2.0));
  return (1.0 - std::sin(kPi * z / 2.0) + alpha * (1.0 + rho_r)) / (2.0 * (1.0 + alpha));
}

double shepp_logan(double x, double y, double z) {
  double value = 0.0;
  for (const Ellipsoid& e : kSheppLogan) {
    const double phi = e.phi_deg * kPi / 180.0;
    const double dx = x - e.x0, dy = y - e.y0, dz = z - e.z0;
    const double u = std::cos(phi) * dx + std::sin(phi) * dy, v = -std::sin(phi) * dx + std::cos(phi) * dy;
    if ((u * u) / (e.a * e.a) + (v * v) / (e.b * e.b) + (dz * dz) / (e.c * e.c) <= 1.0) value += e.intensity;
  }
  return std::clamp(value, 0.0, 1.0);
}

void check_volume_size(const std::array<int64_t, 3>& size, const VolumeLimits& limits, const std::string& what) {
  for (int64_t side : size)
    if (side < 1 || side > limits.max_side_voxels)
      throw InputError(what + ": " + size_text(size) + " voxels: expected 1 to " + std::to_string(limits.max_side_voxels) +
                       " voxels a side (this device's largest 3-D image)");
  const uint64_t bytes = uint64_t(size[0]) * uint64_t(size[1]) * uint64_t(size[2]) * 2;
  if (bytes > limits.max_bytes)
    throw InputError(what + ": " + size_text(size) + " voxels: " + std::to_string(bytes) + " bytes at 16 bits a voxel: expected at most " +
                     std::to_string(limits.max_bytes) + " bytes (this device's largest buffer and the memory available)");
}

std::optional<GeneratedVolume> find_generated_volume(std::string_view name) {
  for (GeneratedVolume kind : {GeneratedVolume::marschner_lobb, GeneratedVolume::combustion, GeneratedVolume::shepp_logan})
    if (generated_volume_name(kind) == name) return kind;
  return std::nullopt;
}

std::string_view generated_volume_name(GeneratedVolume kind) {
  switch (kind) {
    case GeneratedVolume::marschner_lobb: return "marschner-lobb";
    case GeneratedVolume::combustion: return "combustion";
    case GeneratedVolume::shepp_logan: return "shepp-logan";
  }
  return "?";
}

std::string generated_volume_names() { return "marschner-lobb, combustion, shepp-logan"; }

VolumeGrid generate_volume(GeneratedVolume kind, int side, uint64_t seed, const VolumeLimits& limits) {
  check_volume_size({side, side, side}, limits, std::string(generated_volume_name(kind)));
  VolumeGrid grid;
  grid.size_voxels = {side, side, side};
  grid.values.resize(grid.voxel_count());
  const auto coordinate = [side](int i) { return -1.0 + 2.0 * (i + 0.5) / side; };
  size_t index = 0;
  for (int z = 0; z < side; ++z)
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x) {
        const double px = coordinate(x), py = coordinate(y), pz = coordinate(z);
        double value = 0.0;
        switch (kind) {
          case GeneratedVolume::marschner_lobb: value = marschner_lobb(px, py, pz); break;
          // y grows downwards in the grid as on the screen: the flame rises towards -y.
          case GeneratedVolume::combustion: value = combustion(seed, px, -py, pz); break;
          case GeneratedVolume::shepp_logan: value = shepp_logan(px, -py, pz); break;
        }
        grid.values[index++] = quantise(value);
      }
  return grid;
}

namespace {

// Converts raw samples to the 16-bit axis with a range (given or found).
template <class T>
void store_values(const T* samples, uint64_t count, const std::optional<ValueRange>& given, double type_low,
                  double type_high, bool floating, std::vector<uint16_t>& out) {
  ValueRange range{type_low, type_high};
  if (given) {
    range = *given;
  } else if (floating) {
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (uint64_t i = 0; i < count; ++i) {
      const double value = double(samples[i]);
      if (!std::isfinite(value)) continue;
      low = std::min(low, value);
      high = std::max(high, value);
    }
    if (!(low < high)) {  // no finite value, or one value everywhere: it reads as 0
      range = {std::isfinite(low) ? low : 0.0, std::isfinite(low) ? low + 1.0 : 1.0};
    } else {
      range = {low, high};
    }
  }
  const double scale = 1.0 / (range.high - range.low);
  if (!(std::isfinite(scale) && scale > 0.0))
    throw InputError("value range " + std::to_string(range.low) + " to " + std::to_string(range.high) +
                     ": expected a finite span above 0");
  out.resize(count);
  for (uint64_t i = 0; i < count; ++i) {
    const double value = double(samples[i]);
    if (std::isnan(value)) {
      out[i] = 0;
    } else {
      out[i] = quantise((value - range.low) * scale);  // +-inf clamp to the ends
    }
  }
}

std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

std::string teem_error(const std::filesystem::path& path) {
  char* message = biffGetDone(NRRD);
  std::string text = message ? one_line(message) : std::string("unreadable");
  free(message);
  return path.string() + ": " + text + ": expected a 3-D scalar NRRD volume";
}

VolumeGrid load_nrrd(const std::filesystem::path& path, const std::optional<ValueRange>& range, const VolumeLimits& limits) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw InputError(path.string() + ": no such file: expected a NRRD volume (.nrrd or .nhdr)");
  const auto nrrd_deleter = [](Nrrd* nrrd) { nrrdNuke(nrrd); };
  const auto io_deleter = [](NrrdIoState* io) { nrrdIoStateNix(io); };
  // The header first, without the data: the sides are checked before a voxel is allocated.
  std::unique_ptr<Nrrd, decltype(nrrd_deleter)> header(nrrdNew(), nrrd_deleter);
  std::unique_ptr<NrrdIoState, decltype(io_deleter)> io(nrrdIoStateNew(), io_deleter);
  io->skipData = AIR_TRUE;
  if (nrrdLoad(header.get(), path.c_str(), io.get())) throw InputError(teem_error(path));
  if (header->dim != 3)
    throw InputError(path.string() + ": " + std::to_string(header->dim) + " axes: expected a 3-D scalar volume (3 axes)");
  const std::array<int64_t, 3> size{int64_t(header->axis[0].size), int64_t(header->axis[1].size), int64_t(header->axis[2].size)};
  check_volume_size(size, limits, path.string());
  switch (header->type) {
    case nrrdTypeChar: case nrrdTypeUChar: case nrrdTypeShort: case nrrdTypeUShort: case nrrdTypeInt:
    case nrrdTypeUInt: case nrrdTypeFloat: case nrrdTypeDouble: break;
    default:
      throw InputError(path.string() + ": type " + std::string(airEnumStr(nrrdType, header->type)) +
                       ": expected (un)signed 8-, 16- or 32-bit integers, float or double");
  }
  std::unique_ptr<Nrrd, decltype(nrrd_deleter)> nrrd(nrrdNew(), nrrd_deleter);
  if (nrrdLoad(nrrd.get(), path.c_str(), nullptr)) throw InputError(teem_error(path));
  // The file may have changed between the two reads: what was checked must still hold.
  if (nrrd->dim != 3 || nrrd->type != header->type || nrrd->axis[0].size != header->axis[0].size ||
      nrrd->axis[1].size != header->axis[1].size || nrrd->axis[2].size != header->axis[2].size || !nrrd->data)
    throw InputError(path.string() + ": changed while it was read: expected the same 3-D volume twice");
  VolumeGrid grid;
  for (int axis = 0; axis < 3; ++axis) {
    grid.size_voxels[size_t(axis)] = int(size[size_t(axis)]);
    double spacing = nrrd->axis[axis].spacing;
    if (!(std::isfinite(spacing) && spacing > 0.0)) {  // else from the space directions, else 1
      double length = 0.0;
      for (unsigned d = 0; d < nrrd->spaceDim; ++d) length += nrrd->axis[axis].spaceDirection[d] * nrrd->axis[axis].spaceDirection[d];
      spacing = std::isfinite(length) && length > 0.0 ? std::sqrt(length) : 1.0;
    }
    grid.spacing[size_t(axis)] = spacing;
  }
  const double widest = std::max({grid.spacing[0], grid.spacing[1], grid.spacing[2]});
  const double narrowest = std::min({grid.spacing[0], grid.spacing[1], grid.spacing[2]});
  if (!(widest <= 1000.0 * narrowest))
    throw InputError(path.string() + ": spacings " + std::to_string(grid.spacing[0]) + " " + std::to_string(grid.spacing[1]) +
                     " " + std::to_string(grid.spacing[2]) + ": expected the largest at most 1000 times the smallest");
  const uint64_t count = grid.voxel_count();
  const void* data = nrrd->data;
  switch (nrrd->type) {
    case nrrdTypeChar: store_values(static_cast<const int8_t*>(data), count, range, -128, 127, false, grid.values); break;
    case nrrdTypeUChar: store_values(static_cast<const uint8_t*>(data), count, range, 0, 255, false, grid.values); break;
    case nrrdTypeShort: store_values(static_cast<const int16_t*>(data), count, range, -32768, 32767, false, grid.values); break;
    case nrrdTypeUShort: store_values(static_cast<const uint16_t*>(data), count, range, 0, 65535, false, grid.values); break;
    case nrrdTypeInt: store_values(static_cast<const int32_t*>(data), count, range, -2147483648.0, 2147483647.0, false, grid.values); break;
    case nrrdTypeUInt: store_values(static_cast<const uint32_t*>(data), count, range, 0, 4294967295.0, false, grid.values); break;
    case nrrdTypeFloat: store_values(static_cast<const float*>(data), count, range, 0, 1, true, grid.values); break;
    default: store_values(static_cast<const double*>(data), count, range, 0, 1, true, grid.values); break;
  }
  return grid;
}

VolumeGrid load_dat(const std::filesystem::path& path, const std::optional<ValueRange>& range, const VolumeLimits& limits) {
  const std::string expected = "a .dat volume (three little-endian uint16 sides, then uint16 voxels)";
  const std::string bytes = read_input_file(path, expected, limits.max_bytes + 6);
  if (bytes.size() < 6) throw InputError(path.string() + ": " + std::to_string(bytes.size()) + " bytes: expected " + expected);
  const auto u16 = [&bytes](size_t offset) {
    return uint16_t(uint8_t(bytes[offset]) | (uint16_t(uint8_t(bytes[offset + 1])) << 8));
  };
  const std::array<int64_t, 3> size{u16(0), u16(2), u16(4)};
  check_volume_size(size, limits, path.string());
  const uint64_t count = uint64_t(size[0]) * uint64_t(size[1]) * uint64_t(size[2]);
  if (bytes.size() != 6 + 2 * count)
    throw InputError(path.string() + ": " + std::to_string(bytes.size()) + " bytes: expected 6 + 2 x " + size_text(size) +
                     " = " + std::to_string(6 + 2 * count) + " bytes (" + expected + ")");
  std::vector<uint16_t> raw(count);
  uint16_t largest = 0;
  for (uint64_t i = 0; i < count; ++i) {
    raw[i] = u16(6 + 2 * i);
    largest = std::max(largest, raw[i]);
  }
  VolumeGrid grid;
  grid.size_voxels = {int(size[0]), int(size[1]), int(size[2])};
  store_values(raw.data(), count, range, 0, largest <= 4095 ? 4095 : 65535, false, grid.values);
  return grid;
}

}  // namespace

VolumeGrid load_volume_file(const std::filesystem::path& path, const std::optional<ValueRange>& range, const VolumeLimits& limits) {
  if (range && !(std::isfinite(range->low) && std::isfinite(range->high) && range->low < range->high))
    throw InputError(path.string() + ": value range " + std::to_string(range->low) + " to " + std::to_string(range->high) +
                     ": expected finite low < high");
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (extension == ".nrrd" || extension == ".nhdr") return load_nrrd(path, range, limits);
  if (extension == ".dat") return load_dat(path, range, limits);
  throw InputError(path.string() + ": expected a volume file: .nrrd, .nhdr or .dat");
}

}  // namespace fovlab
