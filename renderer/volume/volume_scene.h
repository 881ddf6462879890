#pragma once
// A volume scene: what the volume raycaster draws and how (docs/volume-rendering.md). A small TOML
// file names the volume (a generated one at a size, or a file), its 1-D transfer function (control
// points of colour and opacity on the volume's 0..1 axis) and the camera's orbit; built-in scenes
// are such files in stimuli/volumes/ (marschner-lobb, combustion, shepp-logan), named without their
// extension. Any other name is a path to a .toml volume scene.
//
//   [volume]
//   generator = "marschner-lobb"   # or file = "ct.nrrd" (.nrrd, .nhdr, .dat; relative to this file)
//   size_voxels = 128              # generated volumes
//   seed = 1                       # generated volumes (combustion's noise)
//   value_range = [0.0, 4095.0]    # files: the values that map to 0 and 1 (default: volume_grid.h)
//
//   [camera]                       # an orbit around the volume's centre, in the volume's frame
//   distance = 2.0                 # eye to centre, in the volume's longest sides
//   elevation_deg = 20.0           # above the equator
//   azimuth_deg = 30.0             # at scene time 0
//   orbit_deg_per_s = 0.0          # turn per second of scene time
//   vertical_fov_deg = 40.0        # aperture (full angle)
//
//   [[transfer_point]]             # two or more, values increasing; linear in between
//   value = 0.3
//   colour = [1.0, 0.6, 0.2]       # linear RGB, 0..1
//   opacity = 0.05                 # per reference step (half a voxel), 0..1
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "renderer/volume/volume_grid.h"

namespace fovlab {

struct TransferPoint {
  double value = 0.0;                     // on the volume's 0..1 axis
  std::array<double, 3> colour{0, 0, 0};  // linear RGB
  double opacity = 0.0;                   // per reference step
};

struct VolumeCamera {
  double distance = 2.0;  // in the volume's longest sides, eye to centre
  double elevation_deg = 20.0;
  double azimuth_deg = 30.0;
  double orbit_deg_per_s = 0.0;
  double vertical_fov_deg = 40.0;  // aperture
};

struct VolumeScene {
  std::string name;            // the built-in name, or the file's stem
  std::filesystem::path path;  // the scene file
  std::string text;            // its text (the hash of what the scene is)
  std::optional<GeneratedVolume> generator;
  int size_voxels = 128;  // generated volumes
  uint64_t seed = 1;
  std::filesystem::path volume_file;  // file volumes
  std::optional<ValueRange> value_range;
  std::vector<TransferPoint> transfer_function;
  VolumeCamera camera;
};

std::filesystem::path builtin_volumes_directory();  // stimuli/volumes beside the program (FOVLAB_VOLUMES_DIR overrides)
std::vector<std::string> builtin_volume_names();

// Reads a built-in volume scene by name or a .toml volume scene file. InputError naming the file,
// its line and field, and what was expected.
VolumeScene load_volume_scene(const std::string& name_or_file);

// What a session log records of a scene (replay compares it): the hash of the scene file's text and,
// for a file volume, of the volume file's bytes (and a .nhdr's detached data is not included).
std::string volume_scene_hash(const VolumeScene& scene);

// The scene's volume, generated or read (load_volume_file), within the limits.
VolumeGrid load_scene_volume(const VolumeScene& scene, const VolumeLimits& limits);

// The transfer function as a table of `entries` RGBA values over 0..1 (entry i at value
// i / (entries - 1)), linear between the control points and constant beyond the end ones.
std::vector<std::array<float, 4>> transfer_table(const std::vector<TransferPoint>& points, int entries);

}  // namespace fovlab
