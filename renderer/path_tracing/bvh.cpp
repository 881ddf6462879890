#include "renderer/path_tracing/bvh.h"

#include <algorithm>
#include <array>
#include <limits>

#include <glm/common.hpp>

#include "renderer/path_tracing/path_scene.h"

namespace fovlab {

namespace {

constexpr int kBinCount = 12;
constexpr uint32_t kLeafTriangles = 4;

struct Box {
  glm::vec3 min{std::numeric_limits<float>::infinity()};
  glm::vec3 max{-std::numeric_limits<float>::infinity()};

  void grow(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void grow(const Box& b) {
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
  }
  bool empty() const { return !(min.x <= max.x); }
  float half_area() const {
    if (empty()) return 0.0f;
    const glm::vec3 d = max - min;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
};

struct Builder {
  std::vector<Box> triangle_boxes;
  std::vector<glm::vec3> centroids;
  Bvh bvh;

  Box bounds(uint32_t first, uint32_t count, Box* centroid_bounds) const {
    Box box;
    for (uint32_t i = first; i < first + count; ++i) {
      const uint32_t t = bvh.triangle_order[i];
      box.grow(triangle_boxes[t]);
      centroid_bounds->grow(centroids[t]);
    }
    return box;
  }

  // Splits slots [first, first + count) by the cheapest binned SAH plane; returns the slot where the
  // right half starts, or first when a leaf is cheaper (or nothing separates the centroids).
  uint32_t split(uint32_t first, uint32_t count, const Box& box, const Box& centroid_bounds) {
    float best_cost = std::numeric_limits<float>::infinity();
    int best_axis = -1, best_plane = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const float low = centroid_bounds.min[axis], high = centroid_bounds.max[axis];
      if (!(high > low)) continue;
      std::array<Box, kBinCount> bins;
      std::array<uint32_t, kBinCount> counts{};
      const float scale = float(kBinCount) / (high - low);
      for (uint32_t i = first; i < first + count; ++i) {
        const uint32_t t = bvh.triangle_order[i];
        const int bin = std::min(kBinCount - 1, int((centroids[t][axis] - low) * scale));
        bins[size_t(bin)].grow(triangle_boxes[t]);
        ++counts[size_t(bin)];
      }
      // Sweep from the right for the right-hand areas, then from the left.
      std::array<float, kBinCount> right_area{};
      std::array<uint32_t, kBinCount> right_count{};
      Box right;
      uint32_t right_n = 0;
      for (int b = kBinCount - 1; b > 0; --b) {
        right.grow(bins[size_t(b)]);
        right_n += counts[size_t(b)];
        right_area[size_t(b)] = right.half_area();
        right_count[size_t(b)] = right_n;
      }
      Box left;
      uint32_t left_n = 0;
      for (int plane = 1; plane < kBinCount; ++plane) {  // plane p: bins [0, p) left, [p, end) right
        left.grow(bins[size_t(plane - 1)]);
        left_n += counts[size_t(plane - 1)];
        if (left_n == 0 || right_count[size_t(plane)] == 0) continue;
        const float cost =
            left.half_area() * float(left_n) + right_area[size_t(plane)] * float(right_count[size_t(plane)]);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_plane = plane;
        }
      }
    }
    if (best_axis < 0) return first;
    // A leaf costs count intersections; an interior node one box test (taken as 1) plus its children.
    const float leaf_cost = float(count);
    const float split_cost = 1.0f + best_cost / std::max(box.half_area(), std::numeric_limits<float>::min());
    if (count <= kLeafTriangles && split_cost >= leaf_cost) return first;
    const float low = centroid_bounds.min[best_axis];
    const float scale = float(kBinCount) / (centroid_bounds.max[best_axis] - low);
    auto begin = bvh.triangle_order.begin() + first;
    auto middle = std::partition(begin, begin + count, [&](uint32_t t) {
      return std::min(kBinCount - 1, int((centroids[t][best_axis] - low) * scale)) < best_plane;
    });
    return uint32_t(middle - bvh.triangle_order.begin());
  }

  void build(uint32_t node_index, uint32_t first, uint32_t count, int depth) {
    bvh.depth = std::max(bvh.depth, depth);
    Box centroid_bounds;
    const Box box = bounds(first, count, &centroid_bounds);
    bvh.nodes[node_index].bounds_min = box.min;
    bvh.nodes[node_index].bounds_max = box.max;
    const uint32_t middle = (count <= 1 || depth >= kBvhMaxDepth) ? first : split(first, count, box, centroid_bounds);
    if (middle == first) {
      bvh.nodes[node_index].left_or_first = first;
      bvh.nodes[node_index].triangle_count = count;
      return;
    }
    const auto left = uint32_t(bvh.nodes.size());
    bvh.nodes.emplace_back();
    bvh.nodes.emplace_back();
    bvh.nodes[node_index].left_or_first = left;
    bvh.nodes[node_index].triangle_count = 0;
    build(left, first, middle - first, depth + 1);
    build(left + 1, middle, first + count - middle, depth + 1);
  }
};

}  // namespace

Bvh build_bvh(const PathScene& scene) {
  Builder builder;
  const size_t triangles = scene.triangle_count();
  builder.triangle_boxes.resize(triangles);
  builder.centroids.resize(triangles);
  builder.bvh.triangle_order.resize(triangles);
  for (size_t t = 0; t < triangles; ++t) {
    Box box;
    for (int c = 0; c < 3; ++c) box.grow(scene.positions[scene.indices[3 * t + size_t(c)]]);
    builder.triangle_boxes[t] = box;
    // The vertex mean, not the box centre: the two halves of an axis-aligned quad share a box.
    builder.centroids[t] = (scene.positions[scene.indices[3 * t]] + scene.positions[scene.indices[3 * t + 1]] +
                            scene.positions[scene.indices[3 * t + 2]]) /
                           3.0f;
    builder.bvh.triangle_order[t] = uint32_t(t);
  }
  builder.bvh.nodes.reserve(2 * triangles + 1);
  builder.bvh.nodes.emplace_back();
  builder.build(0, 0, uint32_t(triangles), 1);
  return std::move(builder.bvh);
}

}  // namespace fovlab
