#ifndef FOVLAB_VOLUME_PARAMS_H
#define FOVLAB_VOLUME_PARAMS_H
// The volume raycaster's parameters (volume_raycast.comp.glsl's storage buffer) and the push
// constants of the Voronoi reconstruction (voronoi_reconstruct.comp.glsl); VolumeRaycaster fills
// them (renderer/volume/).
#include "gpu_types.h"

FOVLAB_GPU_BEGIN

struct VolumeRayParams {
  vec4 eye;           // xyz: the camera's position (world)
  vec4 forward;       // xyz: unit view direction; w: tan(vertical fov / 2)
  vec4 right;         // xyz: unit; w: width / height
  vec4 down;          // xyz: unit, screen y grows along it
  vec4 box_half;      // xyz: half the box's extent (world); w: the base step (world)
  vec4 voxel_scale;   // xyz: voxels per world unit along x, y, z; w: the largest iteration count
  uvec4 volume_size;  // xyz: voxels a side; w: voxels a brick side
  uvec4 brick_count;  // xyz: bricks a side; w: 1 = a site is traced only where its readers' box meets the screen
  uvec4 screen;       // x, y: W, H; z: mode; w: sites (MODE_SITES)
  ivec4 mask_offset;  // xy: screen position = mask position - mask_offset; z: jitter seed; w: frame
  vec4 gaze;          // xy: gaze (screen pixels) for the foveated step; z: 1 = foveated step; w: 1 = opacity corrected
  vec4 background;    // rgb; w: the reference step (world), half the smallest voxel, that opacities are given for
  vec4 shading;       // ambient, diffuse, specular, shininess
  vec4 sites_window;  // xy: lowest, zw: highest screen position of a site that is traced
};

struct VoronoiReconstructParams {
  uvec2 screen_size;
  uvec2 mask_size;
  ivec2 mask_offset;   // mask pixel = screen pixel + mask_offset
  uint history_count;  // stored frames to average with, 0 to 8
  uint store_slot;     // slot to store this frame in; 0xFFFFFFFF: none
};

FOVLAB_GPU_END

#endif
