#include "renderer/volume/volume_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/content_hash.h"
#include "core/data_folders.h"
#include "core/input_error.h"
#include "core/input_file.h"
#include "core/toml_fields.h"
#include "core/toml_guard.h"

namespace fovlab {
namespace {

constexpr uint64_t kMaxVolumeSceneBytes = uint64_t(1) << 20;
constexpr int kMaxVolumeSceneNesting = 16;
constexpr size_t kMaxTransferPoints = 4096;

double number_in(const TomlFields& fields, const std::string& key, double fallback, double low, double high,
                 const std::string& expected) {
  const double value = fields.number(key, fallback);
  if (!(value >= low && value <= high)) fields.fail(key, expected);
  return value;
}

}  // namespace

std::filesystem::path builtin_volumes_directory() { return stimuli_subdirectory("FOVLAB_VOLUMES_DIR", "volumes"); }

std::vector<std::string> builtin_volume_names() {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(builtin_volumes_directory(), error))
    if (entry.path().extension() == ".toml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

VolumeScene load_volume_scene(const std::string& name_or_file) {
  VolumeScene scene;
  const bool is_path =
      name_or_file.find('/') != std::string::npos || std::filesystem::path(name_or_file).extension() == ".toml";
  if (is_path) {
    scene.path = name_or_file;
  } else {
    scene.path = builtin_volumes_directory() / (name_or_file + ".toml");
    std::error_code error;
    if (!std::filesystem::is_regular_file(scene.path, error)) {
      std::string known;
      for (const std::string& name : builtin_volume_names()) known += (known.empty() ? "" : ", ") + name;
      throw InputError("volume scene \"" + name_or_file + "\": unknown; expected one of " + known +
                       " or a path to a .toml volume scene");
    }
  }
  scene.name = scene.path.stem().string();
  const std::string path = scene.path.string();
  scene.text = read_input_file(scene.path, "a volume scene (.toml, docs/volume-rendering.md)", kMaxVolumeSceneBytes);
  check_toml_nesting(scene.text, path, kMaxVolumeSceneNesting);
  toml::table root;
  try {
    root = toml::parse(shield_toml_hazards(scene.text, path), path);
  } catch (const toml::parse_error& error) {
    throw InputError(path + ":" + std::to_string(error.source().begin.line) + ": " +
                     unshield_toml_hazards(std::string(error.description())) + " (not valid TOML)");
  }
  const TomlFields fields(root, path, "");
  const TomlFields volume = fields.table("volume");
  const bool has_generator = volume.has("generator"), has_file = volume.has("file");
  if (has_generator == has_file)
    volume.fail("", "expected exactly one of generator (" + generated_volume_names() + ") and file");
  if (has_generator) {
    const std::string generator = unshield_toml_hazards(volume.string("generator"));
    scene.generator = find_generated_volume(generator);
    if (!scene.generator)
      volume.fail("generator", "expected one of " + generated_volume_names() + ", got \"" + generator + "\"");
    const int64_t size = volume.integer("size_voxels", 128);
    if (size < 1 || size > 2048) volume.fail("size_voxels", "expected 1 to 2048 voxels a side");
    scene.size_voxels = int(size);
    const int64_t seed = volume.integer("seed", 1);
    if (seed < 0) volume.fail("seed", "expected a non-negative integer");
    scene.seed = uint64_t(seed);
  } else {
    std::filesystem::path file = unshield_toml_hazards(volume.string("file"));
    if (file.empty()) volume.fail("file", "expected the path of a volume file (.nrrd, .nhdr or .dat), got \"\"");
    if (file.is_relative()) file = scene.path.parent_path() / file;
    scene.volume_file = file.lexically_normal();
    if (volume.has("value_range")) {
      const std::vector<double> range = volume.numbers("value_range");
      if (range.size() != 2 || !(range[0] < range[1]))
        volume.fail("value_range", "expected [low, high] with low < high");
      scene.value_range = ValueRange{range[0], range[1]};
    }
  }
  volume.finish();

  if (const toml::table* camera_table = fields.optional_table("camera")) {
    const TomlFields camera(*camera_table, path, "camera");
    VolumeCamera& c = scene.camera;
    c.distance =
        number_in(camera, "distance", c.distance, 1e-6, 1e6, "expected 1e-6 to 1e6 (the volume's longest sides)");
    c.elevation_deg = number_in(camera, "elevation_deg", c.elevation_deg, -89.0, 89.0, "expected -89 to 89 degrees");
    c.azimuth_deg = number_in(camera, "azimuth_deg", c.azimuth_deg, -360.0, 360.0, "expected -360 to 360 degrees");
    c.orbit_deg_per_s = number_in(camera, "orbit_deg_per_s", c.orbit_deg_per_s, -3600.0, 3600.0,
                                  "expected -3600 to 3600 degrees a second");
    c.vertical_fov_deg = number_in(camera, "vertical_fov_deg", c.vertical_fov_deg, 1.0, 170.0,
                                   "expected 1 to 170 degrees (an aperture)");
    camera.finish();
  }

  const std::vector<TomlFields> points = fields.tables("transfer_point");
  if (points.size() < 2 || points.size() > kMaxTransferPoints)
    fields.fail("transfer_point", "expected 2 to " + std::to_string(kMaxTransferPoints) + " [[transfer_point]] tables");
  for (const TomlFields& point_fields : points) {
    TransferPoint point;
    point.value = point_fields.number("value");  // required, as opacity is: a forgotten key is no silent 0
    if (!(point.value >= 0.0 && point.value <= 1.0)) point_fields.fail("value", "expected 0 to 1 (the volume's axis)");
    if (!scene.transfer_function.empty() && !(point.value > scene.transfer_function.back().value))
      point_fields.fail("value", "expected values that increase from one [[transfer_point]] to the next");
    const std::vector<double> colour = point_fields.numbers("colour");
    if (colour.size() != 3 ||
        std::any_of(colour.begin(), colour.end(), [](double c) { return !(c >= 0.0 && c <= 1.0); }))
      point_fields.fail("colour", "expected [red, green, blue], each 0 to 1 (linear)");
    point.colour = {colour[0], colour[1], colour[2]};
    point.opacity = point_fields.number("opacity");
    if (!(point.opacity >= 0.0 && point.opacity <= 1.0))
      point_fields.fail("opacity", "expected 0 to 1 (per half voxel)");
    point_fields.finish();
    scene.transfer_function.push_back(point);
  }
  fields.finish();
  return scene;
}

std::string volume_scene_hash(const VolumeScene& scene) {
  ContentHash hash;
  hash.add(scene.text);
  if (!scene.generator) {
    std::error_code error;
    const uint64_t size = std::filesystem::file_size(scene.volume_file, error);
    // The volume is read by load_scene_volume within the device's limits; here only hashed.
    hash.add(error ? std::string("missing") : read_input_file(scene.volume_file, "a volume file", size + 1));
  }
  return hash.hex();
}

VolumeGrid load_scene_volume(const VolumeScene& scene, const VolumeLimits& limits) {
  if (scene.generator) return generate_volume(*scene.generator, scene.size_voxels, scene.seed, limits);
  return load_volume_file(scene.volume_file, scene.value_range, limits);
}

std::vector<std::array<float, 4>> transfer_table(const std::vector<TransferPoint>& points, int entries) {
  std::vector<std::array<float, 4>> table(size_t(std::max(entries, 1)));
  for (size_t i = 0; i < table.size(); ++i) {
    const double value = table.size() == 1 ? 0.0 : double(i) / double(table.size() - 1);
    size_t upper = 0;
    while (upper < points.size() && points[upper].value < value) ++upper;
    TransferPoint a, b;
    double t = 0.0;
    if (upper == 0) {
      a = b = points.front();
    } else if (upper == points.size()) {
      a = b = points.back();
    } else {
      a = points[upper - 1];
      b = points[upper];
      t = (value - a.value) / (b.value - a.value);
    }
    for (int c = 0; c < 3; ++c)
      table[i][size_t(c)] = float(a.colour[size_t(c)] + t * (b.colour[size_t(c)] - a.colour[size_t(c)]));
    table[i][3] = float(a.opacity + t * (b.opacity - a.opacity));
  }
  return table;
}

}  // namespace fovlab
