#include "foveation/voronoi_reconstruction.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/natural_neighbor_coordinates_2.h>

#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/input_file.h"
#include "core/output_guard.h"

namespace fovlab {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<uint32_t, Kernel>;
using FaceBase = CGAL::Triangulation_face_base_2<Kernel>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>>;
using Weighted = std::pair<uint32_t, double>;

Delaunay triangulate(const std::vector<MaskSite>& sites) {
  std::vector<std::pair<Kernel::Point_2, uint32_t>> points;
  points.reserve(sites.size());
  for (uint32_t i = 0; i < sites.size(); ++i) points.emplace_back(Kernel::Point_2(sites[i].x_px, sites[i].y_px), i);
  return Delaunay(points.begin(), points.end());
}

uint32_t nearest_site(const std::vector<MaskSite>& sites, double x, double y) {
  uint32_t best = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (uint32_t i = 0; i < sites.size(); ++i) {
    const double dx = sites[i].x_px - x, dy = sites[i].y_px - y, d2 = dx * dx + dy * dy;
    if (d2 < best_d2) {
      best_d2 = d2;
      best = i;
    }
  }
  return best;
}

// Sibson's coordinates through the triangulation; `hint`: a face near the point (the last query's).
std::vector<Weighted> coordinates(const Delaunay& triangulation, const std::vector<MaskSite>& sites, double x, double y,
                                  Delaunay::Face_handle& hint) {
  std::vector<Weighted> weights;
  bool inside = false;
  if (triangulation.dimension() == 2) {
    Delaunay::Vertex_handle neighbour;
    const auto result = CGAL::natural_neighbor_coordinates_2(
        triangulation, Kernel::Point_2(x, y), std::back_inserter(weights),
        [&neighbour](const std::pair<Delaunay::Vertex_handle, Kernel::FT>& entry) {
          neighbour = entry.first;
          return Weighted{entry.first->info(), double(entry.second)};
        },
        hint);
    inside = result.third && result.second > 0.0;
    if (inside) {
      for (Weighted& weight : weights) weight.second /= double(result.second);
      hint = neighbour->face();  // the next pixel's search starts beside this one's
    }
  }
  if (!inside)
    return {{nearest_site(sites, x, y), 1.0}};  // outside the hull, or fewer than 3 sites in general position
  std::sort(weights.begin(), weights.end(), [](const Weighted& a, const Weighted& b) {
    return a.second != b.second ? a.second > b.second : a.first < b.first;
  });
  if (weights.size() > size_t(kVoronoiNeighbours)) {
    weights.resize(kVoronoiNeighbours);
    double sum = 0.0;
    for (const Weighted& weight : weights) sum += weight.second;
    for (Weighted& weight : weights) weight.second /= sum;
  }
  return weights;
}

// The weights of mask rows [first_row, end_row).
void fill_rows(const VoronoiMask& mask, int first_row, int end_row, std::vector<uint32_t>& sites_out,
               std::vector<uint16_t>& weights_out, float& reach_px, std::atomic<int>& rows_done) {
  const Delaunay triangulation = triangulate(mask.sites);  // one a thread: queries need no sharing
  Delaunay::Face_handle hint;
  for (int y = first_row; y < end_row; ++y) {
    for (int x = 0; x < mask.width_px; ++x) {
      const double cx = x + 0.5, cy = y + 0.5;
      const std::vector<Weighted> weights = coordinates(triangulation, mask.sites, cx, cy, hint);
      const size_t base = (size_t(y) * size_t(mask.width_px) + size_t(x)) * kVoronoiNeighbours;
      for (size_t k = 0; k < weights.size(); ++k) {
        sites_out[base + k] = weights[k].first;
        weights_out[base + k] = uint16_t(std::lround(std::clamp(weights[k].second, 0.0, 1.0) * 65535.0));
        if (weights_out[base + k] == 0) continue;  // stored as unused: no reach (deserialise counts alike)
        const MaskSite& site = mask.sites[weights[k].first];
        reach_px = std::max(reach_px, float(std::hypot(site.x_px - cx, site.y_px - cy)));
      }
    }
    rows_done.fetch_add(1, std::memory_order_relaxed);
  }
}

// The cache file: a header, the mask's sites, the weights, then the FNV-1a hash of all before it.
constexpr char kMagic[16] = {'F', 'O', 'V', 'L', 'A', 'B', '-', 'V', 'O', 'R', 'O', 'N', 'O', 'I', '1', '\n'};

}  // namespace

std::string voronoi_settings_key(const VoronoiMaskSettings& s) {
  // v2: bump whenever make_voronoi_mask or the weights change, so no cache of an older algorithm is read.
  std::string text = "voronoi-reconstruction v2;";
  text += std::to_string(s.screen_width_px) + "x" + std::to_string(s.screen_height_px) + ";sigma=";
  char sigma[40];
  std::snprintf(sigma, sizeof sigma, "%.17g", s.density_sigma_px);
  text += sigma;
  char hysteresis[80];
  std::snprintf(hysteresis, sizeof hysteresis, ";h=%.17g,%.17g", s.hysteresis_start, s.hysteresis_step);
  text += hysteresis;
  text += ";initial=" + std::to_string(s.initial_sites) + ";iterations=" + std::to_string(s.max_iterations) +
          ";seed=" + std::to_string(s.seed) + ";neighbours=" + std::to_string(kVoronoiNeighbours);
  return text;
}

namespace {

template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <class T>
bool get(const std::string& in, size_t& offset, T& value) {
  if (in.size() - offset < sizeof(T) || offset > in.size()) return false;
  std::memcpy(&value, in.data() + offset, sizeof(T));
  offset += sizeof(T);
  return true;
}

// The most a cache file of these settings can hold: the header, a site per mask pixel at most (a
// site that owns no pixel is deleted), every pixel's neighbours and the hash. A larger file is not
// read at all.
uint64_t max_cache_file_bytes(const VoronoiMaskSettings& settings, const std::string& key) {
  const uint64_t pixels =
      4 * uint64_t(std::max(settings.screen_width_px, 0)) * uint64_t(std::max(settings.screen_height_px, 0));
  const uint64_t header = sizeof kMagic + 4 + key.size() + 3 * 4 + 1 + 4 + 4;
  return header + pixels * sizeof(MaskSite) + pixels * kVoronoiNeighbours * (sizeof(uint32_t) + sizeof(uint16_t)) + 8;
}

bool deserialise(const std::string& in, const VoronoiMaskSettings& settings, const std::string& key,
                 VoronoiReconstruction& r) {
  if (in.size() < sizeof kMagic + 8 || std::memcmp(in.data(), kMagic, sizeof kMagic) != 0) return false;
  uint64_t stored_hash = 0;
  std::memcpy(&stored_hash, in.data() + in.size() - 8, 8);
  if (ContentHash().add(std::string_view(in.data(), in.size() - 8)).value() != stored_hash) return false;
  size_t offset = sizeof kMagic;
  uint32_t key_size = 0;
  if (!get(in, offset, key_size) || key_size != key.size() || in.compare(offset, key_size, key) != 0) return false;
  offset += key_size;
  int32_t width = 0, height = 0, iterations = 0;
  uint8_t converged = 0;
  uint32_t site_count = 0;
  if (!get(in, offset, width) || !get(in, offset, height) || !get(in, offset, iterations) ||
      !get(in, offset, converged) || !get(in, offset, r.neighbour_reach_px) || !get(in, offset, site_count))
    return false;
  if (width != 2 * settings.screen_width_px || height != 2 * settings.screen_height_px) return false;
  const size_t pixels = size_t(width) * size_t(height) * kVoronoiNeighbours;
  const size_t needed = size_t(site_count) * sizeof(MaskSite) + pixels * (sizeof(uint32_t) + sizeof(uint16_t)) + 8;
  if (in.size() - offset != needed) return false;
  r.settings = settings;
  r.mask.width_px = width;
  r.mask.height_px = height;
  r.mask.iterations = iterations;
  r.mask.converged = converged != 0;
  r.mask.sites.resize(site_count);
  std::memcpy(r.mask.sites.data(), in.data() + offset, site_count * sizeof(MaskSite));
  offset += site_count * sizeof(MaskSite);
  r.neighbour_sites.resize(pixels);
  std::memcpy(r.neighbour_sites.data(), in.data() + offset, pixels * sizeof(uint32_t));
  offset += pixels * sizeof(uint32_t);
  r.neighbour_weights.resize(pixels);
  std::memcpy(r.neighbour_weights.data(), in.data() + offset, pixels * sizeof(uint16_t));
  for (uint32_t index : r.neighbour_sites)
    if (index >= site_count) return false;
  for (const MaskSite& site : r.mask.sites)
    if (!(site.x_px >= 0.0f && site.x_px <= float(width) && site.y_px >= 0.0f && site.y_px <= float(height)))
      return false;
  // The reach decides which sites are traced: recomputed from the weights, never taken on trust.
  if (voronoi_neighbour_reach_px(r) != r.neighbour_reach_px) return false;
  return site_count > 0;
}

}  // namespace

std::string voronoi_cache_bytes(const VoronoiReconstruction& r) {
  const std::string key = voronoi_settings_key(r.settings);
  std::string out(kMagic, sizeof kMagic);
  put(out, uint32_t(key.size()));
  out += key;
  put(out, int32_t(r.mask.width_px));
  put(out, int32_t(r.mask.height_px));
  put(out, int32_t(r.mask.iterations));
  put(out, uint8_t(r.mask.converged));
  put(out, r.neighbour_reach_px);
  put(out, uint32_t(r.mask.sites.size()));
  out.append(reinterpret_cast<const char*>(r.mask.sites.data()), r.mask.sites.size() * sizeof(MaskSite));
  out.append(reinterpret_cast<const char*>(r.neighbour_sites.data()), r.neighbour_sites.size() * sizeof(uint32_t));
  out.append(reinterpret_cast<const char*>(r.neighbour_weights.data()), r.neighbour_weights.size() * sizeof(uint16_t));
  put(out, ContentHash().add(out).value());
  return out;
}

float voronoi_neighbour_reach_px(const VoronoiReconstruction& r) {
  const int width = r.mask.width_px, height = r.mask.height_px;
  float reach = 0.0f;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int k = 0; k < kVoronoiNeighbours; ++k) {
        const size_t entry = (size_t(y) * size_t(width) + size_t(x)) * kVoronoiNeighbours + size_t(k);
        if (r.neighbour_weights[entry] == 0) continue;
        const MaskSite& site = r.mask.sites[r.neighbour_sites[entry]];
        reach = std::max(reach, float(std::hypot(site.x_px - (x + 0.5), site.y_px - (y + 0.5))));
      }
  return reach;
}

std::filesystem::path voronoi_cache_file(const VoronoiMaskSettings& settings,
                                         const std::filesystem::path& cache_folder) {
  return cache_folder / ("voronoi-" + ContentHash().add(voronoi_settings_key(settings)).hex() + ".bin");
}

std::vector<std::pair<uint32_t, double>> sibson_coordinates(const std::vector<MaskSite>& sites, double x_px,
                                                            double y_px) {
  if (sites.empty()) return {};
  const Delaunay triangulation = triangulate(sites);
  Delaunay::Face_handle hint;
  return coordinates(triangulation, sites, x_px, y_px, hint);
}

VoronoiReconstruction make_voronoi_reconstruction(const VoronoiMaskSettings& settings,
                                                  const std::function<void(double)>& progress) {
  VoronoiReconstruction r;
  r.settings = settings;
  r.mask = make_voronoi_mask(settings);
  const size_t entries = size_t(r.mask.width_px) * size_t(r.mask.height_px) * kVoronoiNeighbours;
  r.neighbour_sites.assign(entries, 0);
  r.neighbour_weights.assign(entries, 0);
  const int threads = int(std::clamp<unsigned>(std::thread::hardware_concurrency(), 1, 64));
  const int rows = r.mask.height_px;
  std::vector<float> reach(size_t(threads), 0.0f);
  std::atomic<int> rows_done{0};
  std::vector<std::thread> workers;
  std::exception_ptr failure;
  std::mutex failure_mutex;
  for (int t = 0; t < threads; ++t) {
    const int first = rows * t / threads, end = rows * (t + 1) / threads;
    workers.emplace_back([&, t, first, end] {
      try {
        fill_rows(r.mask, first, end, r.neighbour_sites, r.neighbour_weights, reach[size_t(t)], rows_done);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        rows_done.fetch_add(rows, std::memory_order_relaxed);
      }
    });
  }
  while (progress && rows_done.load(std::memory_order_relaxed) < rows) {
    progress(std::min(1.0, double(rows_done.load(std::memory_order_relaxed)) / rows));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  for (std::thread& worker : workers) worker.join();
  if (failure) std::rethrow_exception(failure);
  if (progress) progress(1.0);
  r.neighbour_reach_px = *std::max_element(reach.begin(), reach.end());
  return r;
}

VoronoiReconstruction cached_voronoi_reconstruction(const VoronoiMaskSettings& settings,
                                                    const std::filesystem::path& cache_folder,
                                                    const std::function<void(double)>& progress, bool* made) {
  const std::string key = voronoi_settings_key(settings);
  const std::filesystem::path file = voronoi_cache_file(settings, cache_folder);
  // Through the input guard: a FIFO, a device or a link to one is never opened for reading (it would
  // block, or feed bytes without end), and a file larger than these settings' masks can be is not read.
  if (const std::optional<std::string> bytes = read_file_if_regular(file, max_cache_file_bytes(settings, key))) {
    VoronoiReconstruction cached;
    if (deserialise(*bytes, settings, key, cached)) {
      if (made) *made = false;
      return cached;
    }
  }
  VoronoiReconstruction made_now = make_voronoi_reconstruction(settings, progress);
  try {  // a cache that cannot be written (a read-only or full disk) costs the next run time, nothing else
    create_output_folder(cache_folder, "");  // through the output guard: never inside a participant's folder
    write_text_atomically(file, voronoi_cache_bytes(made_now));  // binary-safe: written as bytes
  } catch (const std::exception& error) {
    std::fprintf(stderr, "fovlab: warning: the sampling mask was not cached (%s)\n", error.what());
  }
  if (made) *made = true;
  return made_now;
}

}  // namespace fovlab
