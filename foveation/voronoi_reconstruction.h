#pragma once
// How a foveated volume frame is rebuilt from the rays traced at the Voronoi mask's sites (Bruder et al. 2019
// section 4.3): every mask pixel takes a weighted sum of its natural neighbours' colours, with
// Sibson's weights: the share of the pixel's own Voronoi cell, were the pixel's centre inserted as
// a site, that it takes from each site's cell. CGAL (Debian's libcgal-dev) computes them exactly
// (natural_neighbor_coordinates_2 on the sites' Delaunay triangulation). A pixel keeps its 8
// heaviest neighbours, renormalised; a pixel outside the sites' convex hull (at the mask's corners)
// takes its nearest site. The weights depend on the mask only, and the mask moves with the gaze by
// whole pixels, so they are computed once per mask and cached on disk, keyed by the mask's settings.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "foveation/voronoi_mask.h"

namespace fovlab {

inline constexpr int kVoronoiNeighbours = 8;

struct VoronoiReconstruction {
  VoronoiMaskSettings settings;
  VoronoiMask mask;
  // Per mask pixel (row-major), kVoronoiNeighbours entries, heaviest first: a site's index and its weight in
  // 1/65535 (unused entries: weight 0, index 0). The weights of a pixel sum to 65535 within the
  // rounding of each (the shader divides by their sum).
  std::vector<uint32_t> neighbour_sites;
  std::vector<uint16_t> neighbour_weights;
  // The farthest any mask pixel's centre lies from one of its neighbours, in pixels: tracing every
  // site within this margin of the screen gives every screen pixel all its neighbours.
  float neighbour_reach_px = 0.0f;
};

// Sibson's coordinates of the point (x, y) among the sites, as (site index, weight) with weights
// summing to 1, the heaviest first, at most kVoronoiNeighbours (renormalised); outside the convex
// hull, the nearest site with weight 1. The reference of what make_voronoi_reconstruction stores.
std::vector<std::pair<uint32_t, double>> sibson_coordinates(const std::vector<MaskSite>& sites, double x_px,
                                                            double y_px);

// The mask (make_voronoi_mask) and its weights. `progress` is called with the share done (0 to 1)
// now and then while the weights are computed (on all cores).
VoronoiReconstruction make_voronoi_reconstruction(const VoronoiMaskSettings& settings,
                                                  const std::function<void(double)>& progress = {});

// The text that identifies a mask's settings (the cache's key; equal text, equal mask and weights).
std::string voronoi_settings_key(const VoronoiMaskSettings& settings);

// The Voronoi cache's folder inside a pre-render cache folder (stimuli/cache by default).
inline std::filesystem::path voronoi_cache_folder(const std::filesystem::path& cache_root) {
  return cache_root / "voronoi";
}

// The cache's file for these settings in `cache_folder`: voronoi-<hash of voronoi_settings_key>.bin.
std::filesystem::path voronoi_cache_file(const VoronoiMaskSettings& settings,
                                         const std::filesystem::path& cache_folder);

// A cache file's bytes: a header (magic, the settings' key, the mask's size, iterations, whether it
// converged, the reach, the site count), the sites, each pixel's neighbours and weights, then the
// FNV-1a hash of all before it. The hash tells a damaged file from a whole one; it is no seal: whoever
// can write the cache can write a file that passes every check of its own bytes (sessions and replay
// therefore never read the cache, StimulusLibrary makes their masks anew).
std::string voronoi_cache_bytes(const VoronoiReconstruction& reconstruction);

// The reach of a reconstruction's weights (VoronoiReconstruction::neighbour_reach_px), from its sites
// and weights: what a cache file's reach is checked against.
float voronoi_neighbour_reach_px(const VoronoiReconstruction& reconstruction);

// The same through a cache in `cache_folder` (created if missing): voronoi_cache_file, written
// atomically; a file that is not a regular file of at most the size these settings' masks can take
// (a FIFO, a device, a 30 GiB file: never read), unreadable, damaged, of other settings, or whose
// sites or reach do not check out is made anew (and replaced). For commands that render or measure
// (render, bench-volume), not for sessions. `made`, when given, says whether it was computed (true)
// or read (false).
VoronoiReconstruction cached_voronoi_reconstruction(const VoronoiMaskSettings& settings,
                                                    const std::filesystem::path& cache_folder,
                                                    const std::function<void(double)>& progress = {},
                                                    bool* made = nullptr);

}  // namespace fovlab
