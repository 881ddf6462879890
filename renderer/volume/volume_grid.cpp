#include "renderer/volume/volume_grid.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <numbers>
#include <cctype>
#include <cstdint>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>

#include <teem/nrrd.h>

#include "core/input_error.h"
#include "core/input_file.h"
#include "core/number_text.h"
#include "core/prng.h"

namespace fovlab {
namespace {

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
    turbulence += amplitude * std::abs(2.0 * value_noise(seed + uint64_t(octave), x * frequency,
                                                         (y - 0.3 * octave) * frequency, z * frequency) -
                                       1.0);
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
    {1.0, 0.6900, 0.920, 0.810, 0.0, 0.0, 0.0, 0.0},     {-0.8, 0.6624, 0.874, 0.780, 0.0, -0.0184, 0.0, 0.0},
    {-0.2, 0.1100, 0.310, 0.220, 0.22, 0.0, 0.0, -18.0}, {-0.2, 0.1600, 0.410, 0.280, -0.22, 0.0, 0.0, 18.0},
    {0.1, 0.2100, 0.250, 0.410, 0.0, 0.35, -0.15, 0.0},  {0.1, 0.0460, 0.046, 0.050, 0.0, 0.1, 0.25, 0.0},
    {0.1, 0.0460, 0.046, 0.050, 0.0, -0.1, 0.25, 0.0},   {0.1, 0.0460, 0.023, 0.050, -0.08, -0.605, 0.0, 0.0},
    {0.1, 0.0230, 0.023, 0.020, 0.0, -0.606, 0.0, 0.0},  {0.1, 0.0230, 0.046, 0.020, 0.06, -0.605, 0.0, 0.0},
};

}  // namespace

double marschner_lobb(double x, double y, double z) {
  constexpr double alpha = 0.25, f_m = 6.0;
  const double r = std::sqrt(x * x + y * y);
  const double rho_r = std::cos(2.0 * std::numbers::pi * f_m * std::cos(std::numbers::pi * r / 2.0));
  return (1.0 - std::sin(std::numbers::pi * z / 2.0) + alpha * (1.0 + rho_r)) / (2.0 * (1.0 + alpha));
}

double shepp_logan(double x, double y, double z) {
  double value = 0.0;
  for (const Ellipsoid& e : kSheppLogan) {
    const double phi = e.phi_deg * std::numbers::pi / 180.0;
    const double dx = x - e.x0, dy = y - e.y0, dz = z - e.z0;
    const double u = std::cos(phi) * dx + std::sin(phi) * dy, v = -std::sin(phi) * dx + std::cos(phi) * dy;
    if ((u * u) / (e.a * e.a) + (v * v) / (e.b * e.b) + (dz * dz) / (e.c * e.c) <= 1.0) value += e.intensity;
  }
  return std::clamp(value, 0.0, 1.0);
}

void check_volume_size(const std::array<int64_t, 3>& size, const VolumeLimits& limits, const std::string& what) {
  for (int64_t side : size)
    if (side < 1 || side > limits.max_side_voxels)
      throw InputError(what + ": " + size_text(size) + " voxels: expected 1 to " +
                       std::to_string(limits.max_side_voxels) + " voxels a side (this device's largest 3-D image)");
  const uint64_t bytes = uint64_t(size[0]) * uint64_t(size[1]) * uint64_t(size[2]) * 2;
  if (bytes > limits.max_bytes)
    throw InputError(what + ": " + size_text(size) + " voxels: " + std::to_string(bytes) +
                     " bytes at 16 bits a voxel: expected at most " + std::to_string(limits.max_bytes) +
                     " bytes (this device's largest buffer and the memory available)");
}

std::optional<GeneratedVolume> find_generated_volume(std::string_view name) {
  for (GeneratedVolume kind :
       {GeneratedVolume::marschner_lobb, GeneratedVolume::combustion, GeneratedVolume::shepp_logan})
    if (generated_volume_name(kind) == name) return kind;
  return std::nullopt;
}

std::string_view generated_volume_name(GeneratedVolume kind) {
  switch (kind) {
    case GeneratedVolume::marschner_lobb:
      return "marschner-lobb";
    case GeneratedVolume::combustion:
      return "combustion";
    case GeneratedVolume::shepp_logan:
      return "shepp-logan";
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
          case GeneratedVolume::marschner_lobb:
            value = marschner_lobb(px, py, pz);
            break;
          // y grows downwards in the grid as on the screen: the flame rises towards -y.
          case GeneratedVolume::combustion:
            value = combustion(seed, px, -py, pz);
            break;
          case GeneratedVolume::shepp_logan:
            value = shepp_logan(px, -py, pz);
            break;
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
    throw InputError("value range " + exact_number_text(range.low) + " to " + exact_number_text(range.high) +
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

// NRRD through libteem, without letting teem open a path: the header file and every data file it
// names are opened here through the input guard (core/input_file.h: regular files only, a FIFO opened
// without blocking, devices and "-" refused), and teem reads the header from memory and the data
// through /proc/self/fd of the descriptors checked, so what was checked is what is read.
constexpr uint64_t kMaxNrrdHeaderBytes = uint64_t(1) << 20;
constexpr size_t kMaxNrrdDataFiles = 65536;
constexpr const char* kNrrdExpected = "a NRRD volume (.nrrd or .nhdr)";

// The header of an open NRRD file: its lines up to the blank line that ends it (or the end of the
// file), and where the data starts in the file. At most kMaxNrrdHeaderBytes are read.
struct NrrdHeader {
  std::vector<std::string> lines;  // without line ends; the magic first
  uint64_t data_offset = 0;        // bytes of the header and its blank line (attached data starts there)
};

NrrdHeader read_nrrd_header(const OpenInputFile& file) {
  std::string text;
  char buffer[1 << 16];
  size_t end = std::string::npos;  // the blank line's last byte
  bool at_eof = false;
  while (end == std::string::npos && !at_eof) {
    const ssize_t count = ::pread(file.fd(), buffer, sizeof buffer, off_t(text.size()));
    if (count < 0) {
      if (errno == EINTR) continue;
      throw FileError(file.name(), "read", errno);
    }
    if (count == 0) at_eof = true;
    const size_t searched_from = text.size() > 2 ? text.size() - 2 : 0;
    text.append(buffer, size_t(count));
    for (const char* blank : {"\n\n", "\n\r\n"}) {
      const size_t at = text.find(blank, searched_from);
      if (at != std::string::npos && (end == std::string::npos || at + std::strlen(blank) - 1 < end))
        end = at + std::strlen(blank) - 1;
    }
    if (end == std::string::npos && text.size() > kMaxNrrdHeaderBytes)
      throw InputError(file.name() + ": no blank line in its first " + byte_size_text(kMaxNrrdHeaderBytes) +
                       ": expected " + kNrrdExpected + " whose header is at most " +
                       byte_size_text(kMaxNrrdHeaderBytes));
  }
  NrrdHeader header;
  header.data_offset = end == std::string::npos ? text.size() : end + 1;
  text.resize(size_t(header.data_offset));
  size_t start = 0;
  while (start < text.size()) {
    size_t stop = text.find('\n', start);
    if (stop == std::string::npos) stop = text.size();
    std::string line = text.substr(start, stop - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) break;  // the blank line
    header.lines.push_back(std::move(line));
    start = stop + 1;
  }
  return header;
}

// What a header's "data file" field names (teem's three forms: one file; a printf-style template with
// min, max, step and an optional sub-dimension; or LIST with an optional sub-dimension, the names on
// the lines after it), resolved against the header's folder.
struct NrrdDataFiles {
  size_t field_line = 0;     // index in NrrdHeader::lines; 0: no data file field (attached data)
  bool single = true;        // the one-file form
  bool list = false;         // the LIST form
  std::string subdimension;  // as written after the template's numbers or LIST, "" for none
  std::vector<std::filesystem::path> paths;
};

std::string trimmed(std::string_view text) {
  const size_t first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return "";
  const size_t last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}

// The template's names: one conversion %d with an optional 0 flag and width, as NRRD writers make it
// ("slice%03d.raw"). Anything else a printf would read (%s, two conversions) is refused, not formatted.
std::vector<std::string> template_names(const std::filesystem::path& header_path, const std::string& value) {
  const auto fail = [&](const std::string& what) -> void {
    throw InputError(header_path.string() + ": data file \"" + value + "\": " + what);
  };
  std::istringstream words(value);
  std::string pattern;
  long long min = 0, max = 0, step = 0;
  words >> pattern;
  if (!(words >> min >> max >> step)) fail("expected a name with %d, then its first number, last number and step");
  const size_t percent = pattern.find('%');
  size_t digits_end = percent + 1;
  while (digits_end < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[digits_end]))) ++digits_end;
  if (digits_end >= pattern.size() || pattern[digits_end] != 'd' ||
      pattern.find('%', digits_end) != std::string::npos || digits_end - percent - 1 > 2)
    fail("expected one %d conversion (with an optional 0 and width) in the name");
  if (min < INT32_MIN || min > INT32_MAX || max < INT32_MIN || max > INT32_MAX || step == 0 || (max - min) / step < 0 ||
      (max - min) / step >= (long long)kMaxNrrdDataFiles)
    fail("expected a step that reaches the last number from the first in at most " + std::to_string(kMaxNrrdDataFiles) +
         " files");
  // The conversion alone, checked above to be %d with at most two flag or width digits, is safe to
  // give snprintf.
  const std::string conversion = pattern.substr(percent, digits_end - percent) + "lld";
  std::vector<std::string> names;
  for (long long number = min; step > 0 ? number <= max : number >= max; number += step) {
    char digits[32];
    std::snprintf(digits, sizeof digits, conversion.c_str(), number);
    names.push_back(pattern.substr(0, percent) + digits + pattern.substr(digits_end + 1));
  }
  return names;
}

NrrdDataFiles nrrd_data_files(const std::filesystem::path& header_path, const NrrdHeader& header) {
  NrrdDataFiles files;
  std::vector<std::string> names;
  for (size_t i = 1; i < header.lines.size(); ++i) {
    const std::string& line = header.lines[i];
    if (line.empty() || line[0] == '#') continue;
    const size_t colon = line.find(": ");  // a field as teem tells one ("key:=value" is a key/value pair)
    if (colon == std::string::npos) continue;
    if (airEnumVal(nrrdField, line.substr(0, colon).c_str()) != nrrdField_data_file) continue;
    files.field_line = i;
    const std::string value = trimmed(std::string_view(line).substr(colon + 2));
    if (value.find('%') != std::string::npos) {  // the template form
      files.single = false;
      names = template_names(header_path, value);
      std::istringstream words(value);
      std::string skipped;
      for (int word = 0; word < 4; ++word) words >> skipped;
      std::getline(words, files.subdimension);
      files.subdimension = trimmed(files.subdimension);
    } else if (value.rfind(NRRD_LIST_FLAG, 0) == 0) {  // LIST: the rest of the header names the files
      files.single = false;
      files.list = true;
      files.subdimension = trimmed(std::string_view(value).substr(std::strlen(NRRD_LIST_FLAG)));
      for (size_t j = i + 1; j < header.lines.size(); ++j) names.push_back(header.lines[j]);
    } else {
      names.push_back(value);
    }
    break;
  }
  if (files.field_line == 0) return files;
  if (names.empty() || names.size() > kMaxNrrdDataFiles)
    throw InputError(header_path.string() + ": " + std::to_string(names.size()) + " data files: expected 1 to " +
                     std::to_string(kMaxNrrdDataFiles));
  const std::filesystem::path folder = header_path.parent_path();  // empty: the working directory
  for (const std::string& name : names) {
    if (name == "-")
      throw InputError(header_path.string() +
                       ": data file \"-\" (standard input): expected a data file, a regular file "
                       "beside the header or at a path");
    const std::filesystem::path path(name);
    files.paths.push_back(path.is_absolute() ? path : folder / path);
  }
  return files;
}

// The bytes a data file may hold, from the header's sizes and encoding: its share of the values,
// encoded, plus 1 MiB of lines or bytes skipped before them. A larger file is refused before teem
// reads it (a text encoding could otherwise be read without end).
uint64_t max_data_file_bytes(const Nrrd& nrrd, const NrrdIoState& io, size_t file_count) {
  const uint64_t values = uint64_t(nrrdElementNumber(&nrrd)) / file_count;
  const uint64_t bytes = values * uint64_t(nrrdElementSize(&nrrd));
  uint64_t encoded = bytes;                                      // raw
  if (io.encoding == nrrdEncodingAscii) encoded = 64 * values;   // a number and its separator
  else if (io.encoding == nrrdEncodingHex) encoded = 3 * bytes;  // two digits a byte, and line breaks
  else if (io.encoding != nrrdEncodingRaw) encoded = 2 * bytes;  // compressed (gzip, bzip2, zrl)
  return encoded + (uint64_t(1) << 20);
}

std::string encoding_text(const Nrrd& nrrd, const NrrdIoState& io, size_t file_count) {
  return std::to_string(uint64_t(nrrdElementNumber(&nrrd)) / file_count) + " values of " +
         std::string(airEnumStr(nrrdType, nrrd.type)) + " (" + std::string(io.encoding ? io.encoding->name : "?") + ")";
}

struct TeemDeleters {
  void operator()(Nrrd* nrrd) const { nrrdNuke(nrrd); }
  void operator()(NrrdIoState* io) const { nrrdIoStateNix(io); }
  void operator()(FILE* file) const { std::fclose(file); }
};
using NrrdPointer = std::unique_ptr<Nrrd, TeemDeleters>;
using NrrdIoPointer = std::unique_ptr<NrrdIoState, TeemDeleters>;
using FilePointer = std::unique_ptr<FILE, TeemDeleters>;

// One read by teem of the header text (detached data, through /proc/self/fd) or of the header file's
// descriptor from its start (attached data).
void teem_read(Nrrd* nrrd, NrrdIoState* io, const std::string& header_text, const OpenInputFile& header_file,
               bool attached, const std::filesystem::path& path) {
  FilePointer file;
  if (attached) {
    const int copy = ::dup(header_file.fd());
    if (copy < 0) throw FileError(path.string(), "dup", errno);
    file.reset(::fdopen(copy, "rb"));
    if (!file) {
      ::close(copy);
      throw FileError(path.string(), "fdopen", errno);
    }
    std::rewind(file.get());
  } else {
    file.reset(::fmemopen(const_cast<char*>(header_text.data()), header_text.size(), "rb"));
    if (!file) throw FileError(path.string(), "fmemopen", errno);
  }
  if (nrrdRead(nrrd, file.get(), io)) throw InputError(teem_error(path));
}

VolumeGrid load_nrrd(const std::filesystem::path& path, const std::optional<ValueRange>& range,
                     const VolumeLimits& limits) {
  std::error_code error;
  if (!std::filesystem::exists(path, error))
    throw InputError(path.string() + ": no such file: expected " + kNrrdExpected);
  // Any file NRRD can be: a header with its data attached holds at most the largest volume, as doubles
  // written as text (the exact cap, from the header, is checked before teem reads the data).
  const uint64_t largest_data = 64 * (limits.max_bytes / 2) + (uint64_t(1) << 20);
  const OpenInputFile header_file(path, kNrrdExpected, kMaxNrrdHeaderBytes + largest_data);
  const NrrdHeader header = read_nrrd_header(header_file);
  const NrrdDataFiles named = nrrd_data_files(path, header);
  const bool attached = named.field_line == 0;

  // The data files, open and checked; teem gets the header with the field naming them rewritten to
  // their descriptors (the field last, so that a LIST's names end the header).
  std::vector<std::unique_ptr<OpenInputFile>> data_files;
  const std::string data_expected = "the data file of NRRD volume " + path.string();
  for (const std::filesystem::path& file : named.paths)
    data_files.push_back(std::make_unique<OpenInputFile>(file, data_expected, largest_data));
  std::string header_text;
  for (size_t i = 0; i < header.lines.size(); ++i) {
    if (!attached && i == named.field_line) continue;
    if (named.list && i > named.field_line) break;  // a LIST's names: written again below
    header_text += header.lines[i] + "\n";
  }
  if (!attached) {
    const auto descriptor = [](const OpenInputFile& file) { return "/proc/self/fd/" + std::to_string(file.fd()); };
    if (named.single) {
      header_text += "data file: " + descriptor(*data_files.front()) + "\n";
    } else {
      header_text += std::string("data file: ") + NRRD_LIST_FLAG +
                     (named.subdimension.empty() ? "" : " " + named.subdimension) + "\n";
      for (const auto& file : data_files) header_text += descriptor(*file) + "\n";
    }
  }

  // The header first, without the data: the sides and the data files' sizes are checked before a
  // voxel is allocated or a byte of data read.
  NrrdPointer nrrd_header(nrrdNew());
  NrrdIoPointer io(nrrdIoStateNew());
  io->skipData = AIR_TRUE;
  teem_read(nrrd_header.get(), io.get(), header_text, header_file, attached, path);
  if (nrrd_header->dim != 3)
    throw InputError(path.string() + ": " + std::to_string(nrrd_header->dim) +
                     " axes: expected a 3-D scalar volume (3 axes)");
  const std::array<int64_t, 3> size{int64_t(nrrd_header->axis[0].size), int64_t(nrrd_header->axis[1].size),
                                    int64_t(nrrd_header->axis[2].size)};
  check_volume_size(size, limits, path.string());
  switch (nrrd_header->type) {
    case nrrdTypeChar:
    case nrrdTypeUChar:
    case nrrdTypeShort:
    case nrrdTypeUShort:
    case nrrdTypeInt:
    case nrrdTypeUInt:
    case nrrdTypeFloat:
    case nrrdTypeDouble:
      break;
    default:
      throw InputError(path.string() + ": type " + std::string(airEnumStr(nrrdType, nrrd_header->type)) +
                       ": expected (un)signed 8-, 16- or 32-bit integers, float or double");
  }
  const size_t file_count = attached ? 1 : data_files.size();
  const uint64_t cap = max_data_file_bytes(*nrrd_header, *io, file_count);
  const auto check_size = [&](const std::string& name, uint64_t bytes) {
    if (bytes > cap)
      throw InputError(name + ": " + std::to_string(bytes) + " bytes of data: expected at most " + std::to_string(cap) +
                       " for " + encoding_text(*nrrd_header, *io, file_count) + " and 1 MiB skipped (NRRD volume " +
                       path.string() + ")");
  };
  if (attached)
    check_size(path.string(), header_file.size_bytes() - std::min(header_file.size_bytes(), header.data_offset));
  for (const auto& file : data_files) check_size(file->name(), file->size_bytes());

  NrrdPointer nrrd(nrrdNew());
  NrrdIoPointer read_io(nrrdIoStateNew());
  teem_read(nrrd.get(), read_io.get(), header_text, header_file, attached, path);
  // A data file may have grown since its check: what was checked must still hold.
  if (nrrd->dim != 3 || nrrd->type != nrrd_header->type || nrrd->axis[0].size != nrrd_header->axis[0].size ||
      nrrd->axis[1].size != nrrd_header->axis[1].size || nrrd->axis[2].size != nrrd_header->axis[2].size || !nrrd->data)
    throw InputError(path.string() + ": changed while it was read: expected the same 3-D volume twice");
  VolumeGrid grid;
  for (int axis = 0; axis < 3; ++axis) {
    grid.size_voxels[size_t(axis)] = int(size[size_t(axis)]);
    double spacing = nrrd->axis[axis].spacing;
    if (!(std::isfinite(spacing) && spacing > 0.0)) {  // else from the space directions, else 1
      double length = 0.0;
      for (unsigned d = 0; d < nrrd->spaceDim; ++d)
        length += nrrd->axis[axis].spaceDirection[d] * nrrd->axis[axis].spaceDirection[d];
      spacing = std::isfinite(length) && length > 0.0 ? std::sqrt(length) : 1.0;
    }
    grid.spacing[size_t(axis)] = spacing;
  }
  const double widest = std::max({grid.spacing[0], grid.spacing[1], grid.spacing[2]});
  const double narrowest = std::min({grid.spacing[0], grid.spacing[1], grid.spacing[2]});
  if (!(widest <= 1000.0 * narrowest))
    throw InputError(path.string() + ": spacings " + exact_number_text(grid.spacing[0]) + " " +
                     exact_number_text(grid.spacing[1]) + " " + exact_number_text(grid.spacing[2]) +
                     ": expected the largest at most 1000 times the smallest");
  const uint64_t count = grid.voxel_count();
  const void* data = nrrd->data;
  switch (nrrd->type) {
    case nrrdTypeChar:
      store_values(static_cast<const int8_t*>(data), count, range, -128, 127, false, grid.values);
      break;
    case nrrdTypeUChar:
      store_values(static_cast<const uint8_t*>(data), count, range, 0, 255, false, grid.values);
      break;
    case nrrdTypeShort:
      store_values(static_cast<const int16_t*>(data), count, range, -32768, 32767, false, grid.values);
      break;
    case nrrdTypeUShort:
      store_values(static_cast<const uint16_t*>(data), count, range, 0, 65535, false, grid.values);
      break;
    case nrrdTypeInt:
      store_values(static_cast<const int32_t*>(data), count, range, -2147483648.0, 2147483647.0, false, grid.values);
      break;
    case nrrdTypeUInt:
      store_values(static_cast<const uint32_t*>(data), count, range, 0, 4294967295.0, false, grid.values);
      break;
    case nrrdTypeFloat:
      store_values(static_cast<const float*>(data), count, range, 0, 1, true, grid.values);
      break;
    default:
      store_values(static_cast<const double*>(data), count, range, 0, 1, true, grid.values);
      break;
  }
  return grid;
}

VolumeGrid load_dat(const std::filesystem::path& path, const std::optional<ValueRange>& range,
                    const VolumeLimits& limits) {
  const std::string expected = "a .dat volume (three little-endian uint16 sides, then uint16 voxels)";
  const std::string bytes = read_input_file(path, expected, limits.max_bytes + 6);
  if (bytes.size() < 6)
    throw InputError(path.string() + ": " + std::to_string(bytes.size()) + " bytes: expected " + expected);
  const auto u16 = [&bytes](size_t offset) {
    return uint16_t(uint8_t(bytes[offset]) | (uint16_t(uint8_t(bytes[offset + 1])) << 8));
  };
  const std::array<int64_t, 3> size{u16(0), u16(2), u16(4)};
  check_volume_size(size, limits, path.string());
  const uint64_t count = uint64_t(size[0]) * uint64_t(size[1]) * uint64_t(size[2]);
  if (bytes.size() != 6 + 2 * count)
    throw InputError(path.string() + ": " + std::to_string(bytes.size()) + " bytes: expected 6 + 2 x " +
                     size_text(size) + " = " + std::to_string(6 + 2 * count) + " bytes (" + expected + ")");
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

VolumeGrid load_volume_file(const std::filesystem::path& path, const std::optional<ValueRange>& range,
                            const VolumeLimits& limits) {
  if (range && !(std::isfinite(range->low) && std::isfinite(range->high) && range->low < range->high))
    throw InputError(path.string() + ": value range " + std::to_string(range->low) + " to " +
                     std::to_string(range->high) + ": expected finite low < high");
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (extension == ".nrrd" || extension == ".nhdr") return load_nrrd(path, range, limits);
  if (extension == ".dat") return load_dat(path, range, limits);
  throw InputError(path.string() + ": expected a volume file: .nrrd, .nhdr or .dat");
}

}  // namespace fovlab
