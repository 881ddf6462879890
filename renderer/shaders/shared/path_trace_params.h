#ifndef FOVLAB_PATH_TRACE_PARAMS_H
#define FOVLAB_PATH_TRACE_PARAMS_H
// path_trace.comp.glsl's push constants and the scene it reads from storage buffers; PathTracer
// and pack_scene fill them (renderer/path_tracing/).
#include "gpu_types.h"

FOVLAB_GPU_BEGIN

struct PathTraceParams {
  vec4 eye;
  vec4 right;  // camera right scaled by tan(fov / 2) x aspect
  vec4 up;     // camera up scaled by tan(fov / 2)
  vec4 forward;
  vec4 sky_radiance;
  uvec2 size;
  uint sample_begin;
  uint sample_count;
  uint max_bounces;
  uint seed;
  uint emitter_count;  // 0: no next-event estimation
  uint flags;
};

struct BvhNode {
  vec3 bounds_min;
  uint
      left_or_first;  // interior: index of the left child (the right one follows it); leaf: first slot in triangle_order
  vec3 bounds_max;
  uint triangle_count;  // 0: interior node
};

struct Triangle {
  vec3 v0;
  uint material;
  vec3 edge1;                // v1 - v0
  float light_pdf_per_area;  // emitters: probability of picking this triangle / its area; else 0
  vec3 edge2;                // v2 - v0
  uint scene_triangle;       // index in the PathScene
};

struct Material {
  vec3 colour;
  uint kind;  // MaterialKind: 0 lambertian, 1 glass, 2 emissive
  float index_of_refraction;
  float unused0;
  float unused1;
  float unused2;
};

// Emitters are picked with probability proportional to area x mean emitted radiance: the first
// entry whose cdf exceeds a uniform number in [0, 1).
struct Emitter {
  uint slot;  // index into PackedScene::triangles
  float cdf;  // cumulative probability up to and including this emitter; the last is 1
  float unused0;
  float unused1;
};

FOVLAB_GPU_END

#endif
